#include "render/scene_io.h"

#include <cmath>

#include "core/film.h"
#include "integrators/lighttrace/lighttrace.h"
#include "runtime/distributed.h"
#include "runtime/memory_budget.h"
#include "scene/homogeneous_core.h"
#include "render/registry.h"
#include "io/grid_io.h"
#include "core/input_error.h"
#include "io/json_util.h"
#include "io/learned_model_io.h"
#include "io/materials_io.h"
#include "io/mesh_io.h"
#include "io/output_file.h"

namespace pl {

namespace {
constexpr int kMaxImageSide = 16384;

// The render block's keys of one options table (core/option_table.h).
template <class Options>
void readTable(const JsonReader& json, const nlohmann::json& ren, const std::vector<OptionParameter<Options>>& table,
               Options& options) {
    using Kind = typename OptionParameter<Options>::Kind;
    for (const OptionParameter<Options>& p : table) {
        if (!ren.contains(p.name)) continue;
        const double value = p.kind() == Kind::Boolean   ? double(json.boolean(ren, p.name, "render", false))
                             : p.kind() == Kind::Integer ? double(json.integer(ren, p.name, "render"))
                                                         : json.number(ren, p.name, "render");
        const std::string problem = setOption(p, options, value);
        if (!problem.empty()) json.fail(std::string("render.") + p.name, problem);
    }
}

// The render block's keys that are not its own: the estimator's, as given
// (checked against its keys by checkParameters). Paths are taken from the
// scene file's folder.
const std::vector<std::string> kRenderBlockNames = {"integrator", "channel", "channel_sampling", "majorants"};

void readEstimatorParameters(const JsonReader& json, const nlohmann::json& ren, const std::vector<ParameterInfo>& infos,
                             const std::filesystem::path& dir, EstimatorParameters& parameters) {
    using Kind = ParameterInfo::Kind;
    for (const auto& [key, value] : ren.items()) {
        if (findOption(renderParameters(), key) ||
            std::find(kRenderBlockNames.begin(), kRenderBlockNames.end(), key) != kRenderBlockNames.end())
            continue;
        const ParameterInfo* info = findParameter(infos, key);
        const std::string where = "render." + key;
        if (info && info->kind == Kind::Boolean && !value.is_boolean()) json.fail(where, "must be true or false");
        if (info && !info->isText() && info->kind != Kind::Boolean && !value.is_number())
            json.fail(where, "must be a number");
        if (info && info->isText() && !value.is_string()) json.fail(where, "must be a string");
        if (value.is_boolean()) parameters.set(key, value.get<bool>() ? 1.0 : 0.0);
        else if (value.is_number()) parameters.set(key, value.get<double>());
        else if (value.is_string())
            parameters.setText(key, info && info->kind == Kind::Path ? (dir / value.get<std::string>()).string()
                                                                     : value.get<std::string>());
        else json.fail(where, "must be a number, true or false, or a string");
    }
}

SensorKinds sensorKindOf(const SensorDescription& sensor) {
    if (sensor.type != "surface_voxels") return kCameraSensor;
    return sensor.footprint == SurfaceVoxelSensor::Footprint::Patch ? kSurfaceVoxelPatchSensor : kSurfaceVoxelRaySensor;
}

// The sensors of a set as the scene file spells them.
std::string sensorKindsText(SensorKinds kinds) {
    std::vector<std::string> names;
    if (kinds & kCameraSensor) names.push_back("a \"perspective\" or \"orthographic\" sensor");
    if (kinds & kSurfaceVoxelRaySensor) names.push_back("a \"surface_voxels\" sensor with \"footprint\": \"ray\"");
    if (kinds & kSurfaceVoxelPatchSensor) names.push_back("a \"surface_voxels\" sensor with \"footprint\": \"patch\"");
    std::string text;
    for (size_t i = 0; i < names.size(); ++i) text += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
    return text + " only";
}
}  // namespace

std::optional<std::vector<int>> parseChannels(const std::string& s) {
    if (s == "r") return std::vector<int>{0};
    if (s == "g") return std::vector<int>{1};
    if (s == "b") return std::vector<int>{2};
    if (s == "rgb") return std::vector<int>{0, 1, 2};
    return std::nullopt;
}

std::optional<ChannelSampling> parseChannelSampling(const std::string& s) { return parseEnum(kChannelSamplingNames, s); }

const char* channelSamplingName(ChannelSampling s) { return enumName(kChannelSamplingNames, s); }

std::string channelNames(const std::vector<int>& channels) {
    std::string s;
    for (int c : channels) s += "rgb"[c];
    return s;
}

namespace {
// The "object" block: the mesh and how it is placed, labels, materials.
void parseObject(const JsonReader& json, const nlohmann::json& root, const std::filesystem::path& dir,
                 SceneDescription& d) {
    const auto& obj = json.object(root, "object", "");
    json.expectOnlyKeys(obj, "object", {"mesh", "mesh_units", "mesh_scale", "mesh_repair", "labels", "materials", "ior", "void_label",
                                         "homogeneous_core_depth_mm"});
    d.meshFile = dir / json.string(obj, "mesh", "object");
    if (obj.contains("mesh_units")) {
        const std::string unit = json.string(obj, "mesh_units", "object");
        d.meshPlacement.unit = parseLengthUnit(unit);
        if (!d.meshPlacement.unit) json.fail("object.mesh_units", "must be " + enumNames(kLengthUnitNames));
    }
    d.meshPlacement.scale = json.number(obj, "mesh_scale", "object", 1.0);
    d.meshRepair = json.boolean(obj, "mesh_repair", "object", false);
    if (!(d.meshPlacement.scale > 0 && std::isfinite(d.meshPlacement.scale)))
        json.fail("object.mesh_scale", "must be a positive number");
    d.labelsFile = dir / json.string(obj, "labels", "object");
    d.materialsFile = dir / json.string(obj, "materials", "object");
    d.ior = float(json.number(obj, "ior", "object", 1.5));
    if (!(d.ior > 0)) json.fail("object.ior", "must be positive");
    d.homogeneousCoreDepth_mm = float(json.number(obj, "homogeneous_core_depth_mm", "object", 0.0));
    if (!(d.homogeneousCoreDepth_mm >= 0 && std::isfinite(d.homogeneousCoreDepth_mm)))
        json.fail("object.homogeneous_core_depth_mm", "must be a number >= 0 (0: off)");
    if (obj.contains("void_label")) {
        int64_t v = json.integer(obj, "void_label", "object");
        if (v < 0 || v > 255) json.fail("object.void_label", "must be in 0..255");
        d.voidLabel = Label(v);
    }
}

// The "sensor" block.
void parseSensor(const JsonReader& json, const nlohmann::json& root, SensorDescription& s) {
    const auto& sen = json.object(root, "sensor", "");
    s.type = json.string(sen, "type", "sensor");
    if (s.type == "surface_voxels") {
        json.expectOnlyKeys(sen, "sensor", {"type", "footprint"});
        const std::string footprint = json.string(sen, "footprint", "sensor", "ray");
        if (footprint != "ray" && footprint != "patch") json.fail("sensor.footprint", "must be ray or patch");
        s.footprint = footprint == "patch" ? SurfaceVoxelSensor::Footprint::Patch : SurfaceVoxelSensor::Footprint::Ray;
    } else if (s.type == "perspective" || s.type == "orthographic") {
        json.expectOnlyKeys(sen, "sensor", {"type", "position", "look_at", "up", "fov_deg", "width_mm", "resolution"});
        s.pose.position_mm = json.vec3(sen, "position", "sensor");
        s.pose.lookAt_mm = json.vec3(sen, "look_at", "sensor");
        Vec3f fwd = s.pose.lookAt_mm - s.pose.position_mm;
        if (!(length(fwd) > 0)) json.fail("sensor.look_at", "must differ from sensor.position");
        // Default: +z up, or +y for views along the z axis (top-down or bottom-up).
        const bool alongZ = std::abs(fwd.z) > 0.999f * length(fwd);
        s.pose.up = sen.contains("up") ? json.vec3(sen, "up", "sensor") : alongZ ? Vec3f(0, 1, 0) : Vec3f(0, 0, 1);
        if (!(length(cross(fwd, s.pose.up)) > 1e-6f * length(fwd) * length(s.pose.up)))
            json.fail("sensor.up", "must not be parallel to the viewing direction (position to look_at)");
        if (s.type == "perspective") {
            s.fovY_deg = float(json.number(sen, "fov_deg", "sensor", 30.0));
            if (!(s.fovY_deg > 0 && s.fovY_deg < 180)) json.fail("sensor.fov_deg", "must be in (0, 180)");
        } else {
            s.viewWidth_mm = float(json.number(sen, "width_mm", "sensor"));
            if (!(s.viewWidth_mm > 0)) json.fail("sensor.width_mm", "must be positive");
        }
        auto it = sen.find("resolution");
        if (it == sen.end() || !it->is_array() || it->size() != 2 || !(*it)[0].is_number_integer() ||
            !(*it)[1].is_number_integer())
            json.fail("sensor.resolution", "must be [width, height] in pixels");
        int64_t w = (*it)[0].get<int64_t>(), h = (*it)[1].get<int64_t>();
        if (w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide)
            json.fail("sensor.resolution", "must be between 1 and " + std::to_string(kMaxImageSide) + " per side");
        s.width = int(w);
        s.height = int(h);
    } else {
        json.fail("sensor.type", "must be surface_voxels, perspective or orthographic");
    }
}

// The "render" block (the settings' defaults without one), and whether the
// estimator takes the sensor.
void parseRender(const JsonReader& json, const nlohmann::json& root, const std::filesystem::path& dir,
                 SceneDescription& d) {
    const SensorDescription& s = d.sensor;
    RenderSettings& r = d.render;
    r.parameters.materialsFile = d.materialsFile;
    if (root.contains("render")) {
        const auto& ren = json.object(root, "render", "");
        r.integrator = json.string(ren, "integrator", "render", "volpath");
        const IntegratorKind* kind = findIntegratorKind(r.integrator);
        if (!kind) json.fail("render.integrator", "must be " + integratorNames());
        readTable(json, ren, renderParameters(), r);
        readEstimatorParameters(json, ren, kind->factory.parameters(), dir, r.parameters);
        if (auto problem = checkParameters(kind->factory.parameters(), r.parameters, kind->name))
            json.fail("render." + problem->key, problem->what);
        // With a budget or a target, spp is the most samples: none unless given.
        const bool progressive = r.timeBudget_s > 0 || r.targetRelativeError > 0;
        if (progressive && !ren.contains("spp")) r.spp = uint32_t(RenderSettings::kMostSpp);
        auto ch = parseChannels(json.string(ren, "channel", "render", "rgb"));
        if (!ch) json.fail("render.channel", "must be r, g, b or rgb");
        r.channels = *ch;
        r.channelSampling = json.choice(ren, "channel_sampling", "render", kChannelSamplingNames, r.channelSampling);
        r.majorants = json.choice(ren, "majorants", "render", kMajorantsNames, r.majorants);
        if (std::string why = majorantsRefusal(r); !why.empty()) json.fail("render.majorants", why);
        if (std::string why = kind->factory.refusal(r); !why.empty()) json.fail("render.integrator", why);
    }
    if (!(capabilitiesOf(r).sensors & sensorKindOf(s)))
        json.fail("sensor", r.integrator + " takes " + sensorKindsText(capabilitiesOf(r).sensors));
}
}  // namespace

SceneDescription parseScene(const std::filesystem::path& sceneFile) {
    JsonReader json(sceneFile);
    const nlohmann::json& root = json.root();
    if (!root.is_object()) json.fail("", "must be a JSON object");
    json.expectOnlyKeys(root, "", {"object", "environment", "sensor", "render", "output", "comment"});
    SceneDescription d;
    d.sceneFile = sceneFile;
    std::filesystem::path dir = sceneFile.parent_path();

    parseObject(json, root, dir, d);
    // environment
    if (root.contains("environment")) {
        const auto& env = json.object(root, "environment", "");
        json.expectOnlyKeys(env, "environment", {"radiance"});
        d.environment = json.rgb(env, "radiance", "environment");
        for (float v : d.environment)
            if (v < 0) json.fail("environment.radiance", "must not be negative");
    }

    parseSensor(json, root, d.sensor);
    parseRender(json, root, dir, d);
    // output
    if (root.contains("output")) {
        const auto& out = json.object(root, "output", "");
        json.expectOnlyKeys(out, "output", {"path"});
        d.output = json.string(out, "path", "output");
    } else {
        d.output = sceneFile.stem();
    }
    return d;
}

namespace {
// A number as a key of that kind is written: true or false, a whole number, or as it is.
nlohmann::ordered_json numberAs(ParameterInfo::Kind kind, double value) {
    if (kind == ParameterInfo::Kind::Boolean) return value != 0;
    if (kind == ParameterInfo::Kind::Integer) return int64_t(value);
    return value;
}

// The render block's table options that differ from the defaults.
template <class Options>
void writeOptions(const std::vector<OptionParameter<Options>>& table, const Options& options, const Options& defaults,
                  nlohmann::ordered_json& out) {
    const std::vector<ParameterInfo> infos = describe(table);
    for (size_t i = 0; i < table.size(); ++i) {
        const double value = optionValue(table[i], options);
        if (value != optionValue(table[i], defaults)) out[table[i].name] = numberAs(infos[i].kind, value);
    }
}

std::string relativeTo(const std::filesystem::path& target, const std::filesystem::path& fromDir) {
    return std::filesystem::relative(std::filesystem::absolute(target),
                                     std::filesystem::absolute(fromDir.empty() ? "." : fromDir))
        .generic_string();
}

nlohmann::ordered_json renderBlockOf(const SceneDescription& d, const std::filesystem::path& dir) {
    const RenderSettings& r = d.render;
    const RenderSettings defaults;
    nlohmann::ordered_json ren = {{"integrator", r.integrator}};
    // Without spp, a budget or a target takes the most samples.
    RenderSettings tableDefaults;
    if (r.timeBudget_s > 0 || r.targetRelativeError > 0) tableDefaults.spp = uint32_t(RenderSettings::kMostSpp);
    writeOptions(renderParameters(), r, tableDefaults, ren);
    if (r.channels != defaults.channels) ren["channel"] = channelNames(r.channels);
    if (r.channelSampling != defaults.channelSampling)
        ren["channel_sampling"] = enumName(kChannelSamplingNames, r.channelSampling);
    if (r.majorants != defaults.majorants) ren["majorants"] = enumName(kMajorantsNames, r.majorants);
    // The estimator's parameters as given, each as its key reads.
    using Kind = ParameterInfo::Kind;
    const std::vector<ParameterInfo> infos = integratorKindOf(r).factory.parameters();
    for (const auto& [key, value] : r.parameters.numbers()) {
        const ParameterInfo* info = findParameter(infos, key);
        ren[key] = numberAs(info ? info->kind : Kind::Number, value);
    }
    for (const auto& [key, text] : r.parameters.texts()) {
        const ParameterInfo* info = findParameter(infos, key);
        ren[key] = info && info->kind == Kind::Path ? relativeTo(text, dir) : text;
    }
    return ren;
}

nlohmann::ordered_json sensorBlockOf(const SensorDescription& s) {
    nlohmann::ordered_json sen = {{"type", s.type}};
    if (s.type == "surface_voxels") {
        sen["footprint"] = s.footprint == SurfaceVoxelSensor::Footprint::Patch ? "patch" : "ray";
        return sen;
    }
    auto triple = [](const Vec3f& v) { return nlohmann::ordered_json{v.x, v.y, v.z}; };
    sen["position"] = triple(s.pose.position_mm);
    sen["look_at"] = triple(s.pose.lookAt_mm);
    sen["up"] = triple(s.pose.up);
    if (s.type == "perspective") sen["fov_deg"] = s.fovY_deg;
    else sen["width_mm"] = s.viewWidth_mm;
    sen["resolution"] = {s.width, s.height};
    return sen;
}
}  // namespace

void writeScene(const SceneDescription& d, const std::filesystem::path& file) {
    const std::filesystem::path dir = file.parent_path();
    nlohmann::ordered_json object = {{"mesh", relativeTo(d.meshFile, dir)},
                             {"labels", relativeTo(d.labelsFile, dir)},
                             {"materials", relativeTo(d.materialsFile, dir)},
                             {"ior", d.ior}};
    if (d.meshPlacement.unit) object["mesh_units"] = lengthUnitName(*d.meshPlacement.unit);
    if (d.meshPlacement.scale != 1.0) object["mesh_scale"] = d.meshPlacement.scale;
    if (d.meshRepair) object["mesh_repair"] = true;
    if (d.voidLabel) object["void_label"] = int(*d.voidLabel);
    if (d.homogeneousCoreDepth_mm > 0) object["homogeneous_core_depth_mm"] = d.homogeneousCoreDepth_mm;
    const nlohmann::ordered_json scene = {{"object", object},
                                  {"environment", {{"radiance", {d.environment[0], d.environment[1], d.environment[2]}}}},
                                  {"sensor", sensorBlockOf(d.sensor)},
                                  {"render", renderBlockOf(d, dir)},
                                  {"output", {{"path", d.output.generic_string()}}}};
    writeTextFile(file, scene.dump(2) + "\n");
}

Scene loadScene(const SceneDescription& d, SceneNeeds needs) {
    Scene scene;
    scene.ior = d.ior;
    scene.environment = d.environment;
    TriangleMesh mesh = loadMesh(d.meshFile, d.meshPlacement, d.meshRepair);
    MaterialTable materials = loadMaterials(d.materialsFile);
    LabelGrid grid = loadLabelGrid(d.labelsFile, d.voidLabel);

    // Every label in the grid needs a material (the void label may be vacuum).
    auto hist = grid.histogram();
    for (int l = 0; l < 256; ++l)
        if (hist[size_t(l)] > 0 && !materials.covers(Label(l), grid.voidLabel()))
            throw InputError(d.labelsFile.string(),
                             "label " + std::to_string(l) + " (" + std::to_string(hist[size_t(l)]) +
                                 " voxels) is missing from the material table " + d.materialsFile.string());
    if (hist[grid.voidLabel()] == grid.frame().voxelCount())
        throw InputError(d.labelsFile.string(), "grid holds only void voxels");

    // The mesh must overlap the grid.
    scene.worldOrigin_mm = toLocalFrame(mesh, grid);
    scene.geometry = std::make_unique<Geometry>(std::move(mesh));
    Bounds3f mb = scene.geometry->bounds();
    Point3f glo = grid.frame().cornerMin_mm, ghi = grid.frame().cornerMax_mm();
    for (int a = 0; a < 3; ++a)
        if (mb.hi[a] <= glo[a] || mb.lo[a] >= ghi[a])
            throw InputError(d.meshFile.string(), "mesh does not overlap the label grid " + d.labelsFile.string());

    if (d.homogeneousCoreDepth_mm > 0) {
        scene.homogeneousCore.emplace();
        grid = withHomogeneousCore(grid, *scene.geometry, d.homogeneousCoreDepth_mm, &*scene.homogeneousCore);
    }
    GridFrame frame = grid.frame();
    scene.medium = std::make_unique<LabelMedium>(std::move(grid), std::move(materials));
    if (needs.surfaceFields) scene.medium->setSurfaceFields(loadVoxelFields(d.labelsFile, frame));
    if (needs.clearance) scene.clearance = std::make_unique<SurfaceClearance>(*scene.geometry, frame);
    return scene;
}

namespace {
// What rendering allocates per pixel: the film (3 channels of float
// moments) and the output images. Throws if that does not fit.
void requireSensorMemory(const SceneDescription& desc, const Sensor& sensor) {
    uint64_t pixelBytes = uint64_t(sensor.pixelCount()) * 200 + uint64_t(sensor.imageWidth()) * sensor.imageHeight() * 40;
    if (auto why = memoryShortfall(pixelBytes, std::to_string(sensor.pixelCount()) + " sensor pixels", memoryInUseBytes()))
        throw InputError(desc.sceneFile.string(), *why);
}

// The surface-voxel sensor's memory, checked before it is made: the
// largest of its stages, per surface voxel (measured on the 10 mm greek
// cube, docs/performance.md "Memory of the main job"):
//  - the render: the sensor (80 bytes; with the patch footprint and its
//    patches, 100) and the film: in one process one channel's
//    accumulators and two settled channels while the last pass runs
//    (Film::settleChannel), with lighttrace's light tallies (12 bytes for
//    each of LightTrace::mostTalliesAlive(), and the block's two
//    doubles); across MPI ranks lighttrace's share of that, other
//    estimators' all three channels' accumulators;
//  - the images after it: the settled film, the results (24) and 56
//    bytes per atlas pixel;
//  - the result grid, once the film, the sensor and the labels are let go
//    (apps/render_command.cpp): the voxels (12), the results and the two
//    Vec3 grids, whose 8^3 leaves hold about 190 bytes a surface voxel;
//  - the .glb after that: the voxels, the colours (12), the table from
//    voxel to pixel (40) and the baked atlas (about two texels of 12
//    bytes per surface voxel, and their PNG: 30).
// The last two stages come after what is in use now (the scene) is let
// go.
void requireSurfaceSensorMemory(const SceneDescription& desc, const GridFrame& frame, size_t surfaceVoxels) {
    const Vec3i& r = frame.resolution;
    const uint64_t atlasPixels = uint64_t(r.x + r.y + r.z) * 2 * uint64_t(std::max({r.x, r.y, r.z}));
    const uint64_t S = surfaceVoxels, inUse = memoryInUseBytes();
    // The film per surface voxel while rendering, and settled: across
    // ranks lighttrace's films hold each rank's share (and pooling adds
    // rank 0's copy of every pixel's residuals, 16 bytes, and the
    // neighbours asked of other ranks and answered: up to 1.6 for each of
    // a rank's pixels, 32 bytes asking and 44 answering each, so about 64
    // bytes a surface voxel at two ranks, less with more); other
    // estimators' films are whole on every rank.
    const uint64_t ranks = uint64_t(Distributed::ranks());
    const uint64_t oneFilm = Film::bytesPerChannel() + 2 * Film::settledBytesPerChannel(),
                   settled = 3 * Film::settledBytesPerChannel();
    auto filmBytes = [&](bool lighttrace) -> uint64_t {
        if (ranks == 1) return oneFilm;
        return lighttrace ? oneFilm / ranks + 16 + 64 : Film::packedBytesPerPixel();
    };
    auto settledFilmBytes = [&](bool lighttrace) -> uint64_t {
        if (ranks == 1) return settled;
        return lighttrace ? settled + settled / ranks : Film::packedBytesPerPixel();
    };
    auto peakBytes = [&](bool patch, bool lighttrace) {
        const uint64_t sensorBytes = (patch ? 100 : 80) * S;
        const uint64_t tallyBytes = lighttrace ? 16 + 12 * LightTrace::mostTalliesAlive() : 0;
        const uint64_t renderBytes = sensorBytes + (filmBytes(lighttrace) + tallyBytes) * S;
        const uint64_t imageBytes = sensorBytes + (settledFilmBytes(lighttrace) + 24) * S + 56 * atlasPixels;
        const uint64_t afterScene = std::max((12 + 24 + 190) * S, (12 + 12 + 40 + 30) * S);
        return std::max({renderBytes, imageBytes, afterScene - std::min(afterScene, inUse)});
    };
    const bool patch = desc.sensor.footprint == SurfaceVoxelSensor::Footprint::Patch;
    const bool lighttrace = capabilitiesOf(desc.render).lightPathsServeEveryPixel;
    const uint64_t bytes = peakBytes(patch, lighttrace);
    std::string remedy = "a coarser voxel (prepare --voxel) or a smaller model would fit; MPI ranks share only "
                         "lighttrace's film (each holds the whole scene and sensor)";
    // Other estimators or footprints, where they would need less.
    auto offer = [&](uint64_t other, const std::string& what) {
        const uint64_t saved_MiB = (bytes - std::min(bytes, other)) >> 20;
        if (saved_MiB > 0) remedy = what + std::to_string(saved_MiB) + " MiB less; " + remedy;
    };
    if (patch) offer(peakBytes(false, false), "the ray footprint with volpath or printpt needs ");
    if (lighttrace) offer(peakBytes(patch, false), "volpath or printpt need ");
    if (auto why = memoryShortfall(bytes, std::to_string(surfaceVoxels) + " surface voxels", inUse, remedy))
        throw InputError(desc.sceneFile.string(), *why);
}
}  // namespace

std::unique_ptr<SurfaceVoxelSensor> makeSurfaceVoxelSensor(const SceneDescription& desc, const Scene& scene,
                                                           const std::vector<SurfaceVoxel>& surfaceVoxels) {
    requireSurfaceSensorMemory(desc, scene.medium->frame(), surfaceVoxels.size());
    std::unique_ptr<SurfaceVoxelSensor> sensor;
    try {
        sensor = std::make_unique<SurfaceVoxelSensor>(*scene.geometry, scene.medium->frame(), surfaceVoxels,
                                                      desc.sensor.footprint);
    } catch (const std::runtime_error& e) {  // mesh and grid do not match
        throw InputError(desc.labelsFile.string(), e.what());
    }
    return sensor;
}

std::unique_ptr<Sensor> makeSensor(const SceneDescription& desc, const Scene& scene) {
    const SensorDescription& s = desc.sensor;
    if (s.type == "surface_voxels") return makeSurfaceVoxelSensor(desc, scene, scene.medium->grid().surfaceVoxels());
    CameraPose local = s.pose;  // in the scene's local frame
    local.position_mm = local.position_mm - scene.worldOrigin_mm;
    local.lookAt_mm = local.lookAt_mm - scene.worldOrigin_mm;
    std::unique_ptr<Sensor> sensor;
    if (s.type == "perspective")
        sensor = std::make_unique<PerspectiveSensor>(local, s.fovY_deg, s.width, s.height);
    else
        sensor = std::make_unique<OrthographicSensor>(local, s.viewWidth_mm, s.width, s.height);
    requireSensorMemory(desc, *sensor);
    return sensor;
}

}  // namespace pl
