#include "integrators/learned/learned.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Core>

#include "core/input_error.h"
#include "integrators/render_settings.h"
#include "io/learned_model_io.h"
#include "runtime/scheduler.h"

namespace pl {

namespace {
// Elements per batch through the perceptron.
constexpr size_t kBatch = 256;
}  // namespace

std::string LearnedModel::refusal(const MaterialTable& scene, const Vec3f& sceneVoxel_mm) const {
    for (int a = 0; a < 3; ++a)
        if (std::abs(sceneVoxel_mm[a] - voxelSize_mm[a]) > 0.01f * voxelSize_mm[a]) {
            char text[160];
            std::snprintf(text, sizeof(text), "the learned model was trained for %g x %g x %g mm voxels, not %g x %g x %g",
                          voxelSize_mm.x, voxelSize_mm.y, voxelSize_mm.z, sceneVoxel_mm.x, sceneVoxel_mm.y,
                          sceneVoxel_mm.z);
            return text;
        }
    for (int l = 0; l < 256; ++l) {
        const Material &a = scene.byLabel[size_t(l)], &b = materials.byLabel[size_t(l)];
        if (a.defined != b.defined) return "label " + std::to_string(l) + " differs from the material table the learned model was trained for";
        if (!a.defined) continue;
        for (int c = 0; c < 3; ++c) {
            auto close = [](float x, float y) { return std::abs(x - y) <= 1e-4f * std::max(1.0f, std::abs(y)); };
            if (!close(a.sigmaT_perMm[c], b.sigmaT_perMm[c]) || !close(a.albedo[c], b.albedo[c]) || !close(a.g[c], b.g[c]))
                return "material '" + a.name + "' differs from the one the learned model was trained for";
        }
    }
    return {};
}

void evaluateLearnedModel(const LearnedModel& model, const float* inputs, size_t count, float* outputs) {
    using Matrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    using ConstMap = Eigen::Map<const Matrix>;
    // Activations as columns: one column per input row.
    Eigen::MatrixXf x = ConstMap(inputs, Eigen::Index(count), model.descriptorSize).transpose();
    for (size_t l = 0; l < model.layers.size(); ++l) {
        const LearnedModel::Layer& layer = model.layers[l];
        const ConstMap w(layer.weights.data(), layer.outputs, layer.inputs);
        const Eigen::Map<const Eigen::VectorXf> b(layer.bias.data(), layer.outputs);
        Eigen::MatrixXf y = w * x;
        y.colwise() += b;
        if (l + 1 < model.layers.size()) y = y.cwiseMax(0.0f);
        x = std::move(y);
    }
    for (size_t i = 0; i < count; ++i) outputs[i] = x(0, Eigen::Index(i));
}

void describeSurface(const LabelDescriptor& descriptor, const SurfaceVoxelSensor& surface, size_t begin, size_t end,
                     LabelMedium::Tracker& sampler, float* out) {
    std::array<LabelDescriptor::Values, 3> values;
    for (size_t i = begin; i < end; ++i) {
        const SurfacePoint point = surfacePointOf(surface, i);
        descriptor.compute(point.p, point.normal, sampler, values);
        for (int c = 0; c < 3; ++c)
            std::copy(values[size_t(c)].begin(), values[size_t(c)].end(),
                      out + ((i - begin) * 3 + size_t(c)) * LabelDescriptor::kSize);
    }
}

namespace {
std::filesystem::path modelFileOf(const EstimatorParameters& parameters) {
    const std::string* file = parameters.text("learned_model");
    return file ? std::filesystem::path(*file) : learnedModelBeside(parameters.materialsFile);
}
}  // namespace

std::vector<ParameterInfo> Learned::parameters() {
    ParameterInfo model;
    model.name = "learned_model";
    model.kind = ParameterInfo::Kind::Path;
    model.doc = "the learned predictor's model file; default: the one beside the material table";
    return {model};
}

std::string Learned::refusal(const RenderSettings& settings) {
    std::string why = refusalWithoutReentry("learned", settings);
    if (why.empty()) try {
            loadLearnedModel(modelFileOf(settings.parameters));
        } catch (const std::exception& e) {
            why = e.what();
        }
    return why;
}

std::unique_ptr<Integrator> Learned::create(const Scene& scene, const Sensor& sensor, const RenderSettings& settings) {
    return std::make_unique<Learned>(scene, sensor, loadLearnedModel(modelFileOf(settings.parameters)));
}

Learned::Learned(const Scene& scene, const Sensor& sensor, std::shared_ptr<const LearnedModel> model)
    : SurfaceResponse(scene, sensor) {
    const LabelMedium& medium = *scene.medium;
    if (std::string why = model->refusal(medium.materials(), medium.frame().voxelSize_mm); !why.empty())
        throw InputError(model->file, why);
    if (model->descriptorSize != LabelDescriptor::kSize)
        throw InputError(model->file, "the model reads descriptors of " + std::to_string(model->descriptorSize) +
                                          " values, this program makes " + std::to_string(LabelDescriptor::kSize));
    std::unique_ptr<LabelDescriptor> made;
    try {
        made = std::make_unique<LabelDescriptor>(medium, LabelDescriptor::kMostPyramidBytes);
    } catch (const std::exception& e) {
        throw InputError(model->file, std::string("cannot describe this object: ") + e.what());
    }
    const LabelDescriptor& descriptor = *made;
    const size_t n = elementCount();
    parallelForTiles(n, kBatch, [&](size_t begin, size_t end) {
        LabelMedium::Tracker sampler(medium);
        const size_t count = end - begin;
        std::vector<float> inputs(3 * count * LabelDescriptor::kSize), outputs(3 * count);
        describeSurface(descriptor, surface(), begin, end, sampler, inputs.data());
        evaluateLearnedModel(*model, inputs.data(), 3 * count, outputs.data());
        for (size_t i = begin; i < end; ++i)
            for (int c = 0; c < 3; ++c) {
                const float R = std::max(0.0f, outputs[(i - begin) * 3 + size_t(c)]);
                response_[i][c] = R;
                errorBound_[i][c] = model->errorShare * R + model->errorFloor;
            }
    });
    coverElementsOverClearResin();
}

}  // namespace pl
