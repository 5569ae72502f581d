// Python bindings of the prediction API (pybind11, numpy arrays in and out):
//   import printlight
//   p = printlight.Predictor("scene.json")
//   r = p.predict()          # dict of numpy arrays, see docs/api.md
//   p.change_labels(voxels, labels)
//   printlight.prepare("model.gltf", "out.vdb", voxel_mm=(0.0423, 0.0847, 0.027))
// C++ exceptions arrive as RuntimeError (bad files), ValueError (bad labels
// or grids) and IndexError (voxels outside the grid).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "api/predictor.h"
#include "io/grid_io.h"
#include "io/mesh_io.h"
#include "io/output_file.h"
#include "prepare/prepare_model.h"
#include "render/registry.h"
#include "render/scene_io.h"

namespace py = pybind11;

namespace pl {
namespace {

using Labels3d = py::array_t<uint8_t, py::array::c_style | py::array::forcecast>;

py::dict toDict(const SurfacePrediction& p) {
    const py::ssize_t n = py::ssize_t(p.radiance.size());
    py::array_t<int32_t> voxels({n, py::ssize_t(3)});
    py::array_t<float> radiance({n, py::ssize_t(3)}), stderror({n, py::ssize_t(3)});
    py::array_t<uint32_t> samples(n);
    auto v = voxels.mutable_unchecked<2>();
    auto r = radiance.mutable_unchecked<2>();
    auto e = stderror.mutable_unchecked<2>();
    auto s = samples.mutable_unchecked<1>();
    for (py::ssize_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
            v(i, c) = p.voxels[size_t(i)][c];
            r(i, c) = p.radiance[size_t(i)][c];
            e(i, c) = p.standardError[size_t(i)][c];
        }
        s(i) = p.samples[size_t(i)];
    }
    py::dict d;
    d["voxels"] = voxels;
    d["radiance"] = radiance;
    d["stderr"] = stderror;
    d["samples"] = samples;
    d["update_seconds"] = p.updateSeconds;
    d["render_seconds"] = p.renderSeconds;
    d["retraced_voxels"] = p.retracedVoxels;
    d["started_afresh"] = p.startedAfresh;
    return d;
}

void changeLabels(Predictor& p, py::array_t<int32_t, py::array::c_style | py::array::forcecast> voxels,
                  py::array_t<uint8_t, py::array::c_style | py::array::forcecast> labels) {
    if (voxels.ndim() != 2 || voxels.shape(1) != 3) throw std::invalid_argument("voxels must be an (N, 3) array");
    if (labels.ndim() != 1 || labels.shape(0) != voxels.shape(0))
        throw std::invalid_argument("labels must be an (N,) array, one per voxel");
    auto v = voxels.unchecked<2>();
    auto l = labels.unchecked<1>();
    std::vector<LabelGrid::Change> changes(size_t(voxels.shape(0)));
    for (py::ssize_t i = 0; i < voxels.shape(0); ++i) changes[size_t(i)] = {{v(i, 0), v(i, 1), v(i, 2)}, l(i)};
    p.changeLabels(changes);
}

// The grid as a dense (nz, ny, nx) array (x fastest, like the .bin format).
Labels3d labelsOf(const Predictor& p) {
    const GridFrame& f = p.labels().frame();
    std::vector<Label> dense = p.labels().toDense();
    Labels3d out({py::ssize_t(f.resolution.z), py::ssize_t(f.resolution.y), py::ssize_t(f.resolution.x)});
    std::copy(dense.begin(), dense.end(), out.mutable_data());
    return out;
}

void setLabels(Predictor& p, Labels3d dense) {
    const GridFrame& f = p.labels().frame();
    if (dense.ndim() != 3 || dense.shape(0) != f.resolution.z || dense.shape(1) != f.resolution.y ||
        dense.shape(2) != f.resolution.x)
        throw std::invalid_argument("labels must be a (" + std::to_string(f.resolution.z) + ", " +
                                    std::to_string(f.resolution.y) + ", " + std::to_string(f.resolution.x) +
                                    ") uint8 array (z, y, x)");
    std::vector<Label> labels(dense.data(), dense.data() + dense.size());
    p.setLabels(LabelGrid::fromDense(f, labels, p.labels().voidLabel()));
}

// prepare as the command line runs it (prepare/prepare_model.h): reads the
// model, writes labels, sdf and normal grids to `output`; returns counts.
py::dict prepare(const std::string& model, const std::string& output, std::array<float, 3> voxel_mm,
                 float extrude_mm, float margin_mm, std::optional<std::array<float, 3>> color,
                 const std::string& halftone, std::optional<std::string> units) {
    if (std::filesystem::path(output).extension() != ".vdb") throw std::invalid_argument("output must be a .vdb file");
    const std::optional<HalftoneMethod> method = parseEnum(kHalftoneMethodNames, halftone);
    if (!method) throw std::invalid_argument("halftone must be " + enumNames(kHalftoneMethodNames));
    MeshPlacement placement;
    if (units) {
        placement.unit = parseLengthUnit(*units);
        if (!placement.unit) throw std::invalid_argument("units must be " + enumNames(kLengthUnitNames));
    }
    refuseToOverwriteInputs(output, {model});
    PrepareSettings settings;
    settings.voxel_mm = {voxel_mm[0], voxel_mm[1], voxel_mm[2]};
    settings.extrude_mm = extrude_mm;
    settings.margin_mm = margin_mm;
    if (color) settings.color = RGB{(*color)[0], (*color)[1], (*color)[2]};
    settings.halftone = *method;
    MeshAsset asset = loadMeshAsset(model, placement);
    Geometry geometry(std::move(asset.mesh));
    PreparedModel prepared = prepareModel(geometry, asset.appearance, settings);
    writePreparedVdb(prepared.labels, prepared.fields, output);
    const Vec3i r = prepared.labels.frame().resolution;
    py::dict d;
    d["resolution"] = std::vector<int>{r.x, r.y, r.z};
    d["printed_voxels"] = prepared.printedVoxels;
    d["shell_voxels"] = prepared.shellVoxels;
    d["surface_voxels"] = prepared.labels.surfaceVoxels().size();
    d["color_source"] = prepared.colorSource;
    return d;
}

// The defaults the keyword arguments show: the library's own.
const AdaptiveSampling kAdaptive{};
const PrepareSettings kPrepare{};

}  // namespace
}  // namespace pl

PYBIND11_MODULE(printlight, m) {
    using namespace pl;
    m.doc() = "printlight: surface-radiance prediction of full-colour 3D prints (docs/api.md)";
    py::class_<Predictor>(m, "Predictor")
        .def(py::init([](const std::string& scene) { return Predictor::fromSceneFile(scene); }), py::arg("scene"),
             "Loads a scene JSON (sensor surface_voxels): mesh, BVH, sensor and materials, once.")
        .def("predict", [](Predictor& p) { return toDict(p.predict()); },
             "Renders the current labels: dict with voxels (N,3) int32, radiance and stderr (N,3) float32, "
             "samples (N,) uint32, update_seconds, render_seconds, retraced_voxels, started_afresh.")
        .def("change_labels", &changeLabels, py::arg("voxels"), py::arg("labels"),
             "Relabels voxels: (N,3) grid indices and (N,) labels (the void label empties a voxel).")
        .def("labels", &labelsOf, "The current labels as a dense (nz, ny, nx) uint8 array.")
        .def("set_labels", &setLabels, py::arg("labels"), "Replaces the labels with a dense (nz, ny, nx) uint8 array.")
        .def_property_readonly("grid_min", [](const Predictor& p) {
            Vec3i v = p.labels().frame().indexMin;
            return std::vector<int>{v.x, v.y, v.z};
        }, "Index of the dense array's first voxel (x, y, z).")
        .def_property_readonly("void_label", [](const Predictor& p) { return int(p.labels().voidLabel()); })
        .def_property_readonly("surface_voxel_count", &Predictor::surfaceVoxelCount)
        .def_property("spp", [](Predictor& p) { return p.settings().spp; },
                      [](Predictor& p, uint32_t v) {
                          if (v < 1) throw std::invalid_argument("spp must be at least 1");
                          p.settings().spp = v;
                      })
        .def_property("carry_over", [](Predictor& p) { return p.carryOver().enabled; },
                      [](Predictor& p, bool on) { p.carryOver().enabled = on; },
                      "keep the samples that label changes cannot reach; each predict adds spp more (docs/api.md)")
        .def_property("seed", [](Predictor& p) { return p.settings().seed; },
                      [](Predictor& p, uint64_t v) { p.settings().seed = v; })
        .def_property("integrator", [](Predictor& p) { return p.settings().integrator; },
                      [](Predictor& p, const std::string& v) {
                          if (!findIntegratorKind(v))
                              throw std::invalid_argument("integrator must be " + integratorNames());
                          setIntegrator(p.settings(), v);
                      })
        .def_property("channels", [](Predictor& p) { return channelNames(p.settings().channels); },
                      [](Predictor& p, const std::string& v) {
                          auto ch = parseChannels(v);
                          if (!ch) throw std::invalid_argument("channels must be r, g, b or rgb");
                          p.settings().channels = *ch;
                      })
        .def_property("channel_sampling",
                      [](Predictor& p) { return std::string(channelSamplingName(p.settings().channelSampling)); },
                      [](Predictor& p, const std::string& v) {
                          auto sampling = parseChannelSampling(v);
                          if (!sampling) throw std::invalid_argument("channel_sampling must be " + enumNames(kChannelSamplingNames));
                          p.settings().channelSampling = *sampling;
                      })
        .def("set_adaptive",
             [](Predictor& p, float maxStandardError, float maxRelativeError, uint32_t firstRoundSpp, uint32_t roundSpp,
                uint32_t maxSpp, double maxSeconds) {
                 p.adaptive() = {true, maxStandardError, maxRelativeError, firstRoundSpp, roundSpp, maxSpp, maxSeconds};
             },
             py::arg("max_standard_error") = kAdaptive.maxStandardError,
             py::arg("max_relative_error") = kAdaptive.maxRelativeError,
             py::arg("first_round_spp") = kAdaptive.firstRoundSpp, py::arg("round_spp") = kAdaptive.roundSpp,
             py::arg("max_spp") = kAdaptive.maxSpp, py::arg("max_seconds") = kAdaptive.maxSeconds,
             "Adaptive sampling: render until every voxel's standard error meets the target (see docs/api.md).")
        .def("adaptive_off", [](Predictor& p) { p.adaptive().enabled = false; });
    m.def("prepare", &prepare, py::arg("model"), py::arg("output"),
          py::arg("voxel_mm") = std::array<float, 3>{kPrinterVoxel_mm.x, kPrinterVoxel_mm.y, kPrinterVoxel_mm.z},
          py::arg("extrude_mm") = kPrepare.extrude_mm, py::arg("margin_mm") = kPrepare.margin_mm,
          py::arg("color") = py::none(), py::arg("halftone") = enumName(kHalftoneMethodNames, kPrepare.halftone),
          py::arg("units") = py::none(),
          "Voxelises and halftones a closed, textured mesh (.gltf, .glb, .obj) into a prepared .vdb, as "
          "`printlight prepare` does; units: 'm', 'mm' or 'in' (default: glTF's metres, OBJ's millimetres); "
          "returns a dict of counts.");
}
