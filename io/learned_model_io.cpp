#include "io/learned_model_io.h"

#include <map>
#include <mutex>

#include "core/input_error.h"
#include "io/json_util.h"
#include "io/materials_io.h"

namespace pl {

namespace {

std::shared_ptr<const LearnedModel> readLearnedModel(const std::filesystem::path& file) {
    if (!std::filesystem::exists(file))
        throw InputError(file.string(), "no learned model (scripts/train_learned.py --materials TABLE trains one "
                                        "beside the table; render.learned_model names another)");
    JsonReader json(file);
    const nlohmann::json& root = json.root();
    json.expectOnlyKeys(root, "", {"format", "comment", "trained_for", "descriptor_size", "layers", "error_bound", "training"});
    if (json.string(root, "format", "") != "printlight-learned-1") json.fail("format", "must be printlight-learned-1");
    auto model = std::make_shared<LearnedModel>();
    model->file = file.string();
    const nlohmann::json& trained = json.object(root, "trained_for", "");
    json.expectOnlyKeys(trained, "trained_for", {"materials", "voxel_size_mm"});
    if (!trained.contains("materials")) json.fail("trained_for.materials", "is missing");
    model->materials = readMaterials(json, trained["materials"]);
    const RGB voxel = json.rgb(trained, "voxel_size_mm", "trained_for");
    model->voxelSize_mm = {voxel[0], voxel[1], voxel[2]};
    model->descriptorSize = int(json.integer(root, "descriptor_size", ""));
    if (!root.contains("layers") || !root["layers"].is_array() || root["layers"].empty())
        json.fail("layers", "must be a non-empty list");
    int inputs = model->descriptorSize;
    for (size_t i = 0; i < root["layers"].size(); ++i) {
        const nlohmann::json& l = root["layers"][i];
        const std::string where = "layers[" + std::to_string(i) + "]";
        json.expectOnlyKeys(l, where, {"inputs", "outputs", "weights", "bias"});
        LearnedModel::Layer layer;
        layer.inputs = int(json.integer(l, "inputs", where));
        layer.outputs = int(json.integer(l, "outputs", where));
        if (layer.inputs != inputs || layer.outputs < 1) json.fail(where, "does not follow the previous layer");
        try {
            layer.weights = l.at("weights").get<std::vector<float>>();
            layer.bias = l.at("bias").get<std::vector<float>>();
        } catch (const nlohmann::json::exception&) {
            json.fail(where, "needs number lists weights and bias");
        }
        if (layer.weights.size() != size_t(layer.inputs) * size_t(layer.outputs) || layer.bias.size() != size_t(layer.outputs))
            json.fail(where, "weights or bias has the wrong length");
        inputs = layer.outputs;
        model->layers.push_back(std::move(layer));
    }
    if (inputs != 1) json.fail("layers", "the last layer must have one output");
    const nlohmann::json& bound = json.object(root, "error_bound", "");
    model->errorShare = float(json.number(bound, "share", "error_bound"));
    model->errorFloor = float(json.number(bound, "floor", "error_bound"));
    return model;
}

}  // namespace

std::shared_ptr<const LearnedModel> loadLearnedModel(const std::filesystem::path& file) {
    static std::mutex mutex;
    static std::map<std::filesystem::path, std::shared_ptr<const LearnedModel>> models;
    std::lock_guard<std::mutex> lock(mutex);
    auto& model = models[file];
    if (!model) model = readLearnedModel(file);
    return model;
}

std::filesystem::path learnedModelBeside(const std::filesystem::path& materialsFile) {
    std::filesystem::path model = materialsFile;
    model.replace_extension(".learned.json");
    return model;
}

}  // namespace pl
