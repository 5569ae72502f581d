#include "testing/stability_cases.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include <unistd.h>

#include "render/render.h"
#include "testing/synthetic_scene.h"
#include "io/grid_io.h"
#include "core/input_error.h"
#include "io/mesh_io.h"
#include "render/scene_io.h"

namespace pl {

namespace {

using namespace synthetic;

// One ray per pixel, the same for every sample: rays exactly along the grid
// axes and on voxel faces and edges (a camera would jitter them off).
class FixedRaySensor : public Sensor {
public:
    explicit FixedRaySensor(std::vector<Ray> rays) : rays_(std::move(rays)) {}
    size_t pixelCount() const override { return rays_.size(); }
    Ray generateRay(size_t pixel, float, float) const override { return rays_[pixel]; }
    int imageWidth() const override { return int(rays_.size()); }
    int imageHeight() const override { return 1; }

private:
    std::vector<Ray> rays_;
};

using SceneFactory = std::function<Scene()>;
using SensorFactory = std::function<std::unique_ptr<Sensor>(const Scene&)>;

enum class Expect { Value, OtherEstimator, SameSceneAtOrigin };

struct Case {
    Case(std::string n, std::string p, SceneFactory sc, SensorFactory se)
        : name(std::move(n)), parameters(std::move(p)), scene(std::move(sc)), sensor(std::move(se)) {}
    std::string name, parameters;
    SceneFactory scene;
    SensorFactory sensor;
    Expect expect = Expect::Value;
    double expected = 0;
    std::string source;
    uint32_t spp = 16;
    bool quick = false;        // part of --quick
    // Leaks: collisions within float round-off of the boundary that land
    // on its far side; they leave, as they nearly did. Their share bounds
    // the bias they can cause.
    double maxLeakFraction = 1e-3;
    SceneFactory originScene;  // Expect::SameSceneAtOrigin
};

struct Measurement {
    double mean = 0, stdErr = 0;
    uint64_t nonFinite = 0;
    PathStats stats;
    double seconds = 0;
};

// Mean over all pixels of channel 0 and its standard error (pixels are
// independent: sqrt(sum of squared standard errors) / pixels).
Measurement measure(const Scene& scene, const Sensor& sensor, const std::string& integrator, uint32_t spp,
                    uint64_t seed) {
    RenderSettings rs;
    rs.integrator = integrator;
    rs.spp = spp;
    rs.seed = seed;
    rs.channels = {0};
    rs.reentry = false;
    RenderResult r = render(scene, sensor, rs);
    Measurement m;
    double sum = 0, var = 0;
    size_t n = 0;
    for (size_t p = 0; p < r.film.pixelCount(); ++p) {
        double v = r.film.mean(p, 0), s = r.film.standardError(p, 0);
        if (!std::isfinite(v) || !std::isfinite(s)) {
            ++m.nonFinite;
            continue;
        }
        sum += v;
        var += s * s;
        ++n;
    }
    m.mean = n ? sum / double(n) : 0.0;
    m.stdErr = n ? std::sqrt(var) / double(n) : 0.0;
    m.stats = r.stats;
    m.seconds = r.seconds;
    return m;
}

// z of a difference; values that agree to float round-off count as exact
// even when both standard errors are zero (deterministic estimators).
double zScore(double measured, double stdErr, double expected, double expectedStdErr) {
    double d = measured - expected;
    double roundOff = 1e-6 * std::max(std::abs(expected), std::abs(measured)) + 1e-12;
    return d / std::sqrt(stdErr * stdErr + expectedStdErr * expectedStdErr + roundOff * roundOff);
}

void judge(StabilityRow& row) {
    row.z = zScore(row.measured, row.stdErr, row.expected, row.expectedStdErr);
    row.pass = std::abs(row.z) < kStabilityZLimit && row.nonFinite == 0;
    auto problem = [&row](const char* what) {
        row.pass = false;
        row.note += row.note.empty() ? what : std::string("; ") + what;
    };
    if (row.nonFinite) problem("NaN/Inf pixels");
    // Numerical leaks (a ray inside that misses the boundary) are counted as
    // leaving; a handful per million paths is round-off at edges.
    if (double(row.leaks) > row.maxLeakFraction * double(row.paths) + 1) problem("leaks above the budget");
    if (row.trapped) problem("trapped paths");
}

// ---- scenes -------------------------------------------------------------

constexpr Label kA = 1, kB = 2;

RGB gray(double v) { return {float(v), float(v), float(v)}; }

MaterialTable oneMaterial(double sigmaT, double albedo, double g = 0) {
    return tableOf({{kA, material(gray(sigmaT), gray(albedo), gray(g))}});
}

SceneFactory cube(float size_mm, float voxel_mm, MaterialTable table, float ior, Point3f corner = {0, 0, 0}) {
    return [=] {
        int n = int(std::lround(size_mm / voxel_mm));
        return boxScene({n, n, n}, {voxel_mm, voxel_mm, voxel_mm}, [](const Vec3i&) { return kA; }, table, ior,
                        {1, 1, 1}, corner);
    };
}

// 2 x 2 mm in x-y, `thickness` in z from z = 0, in 0.1 mm voxels.
SceneFactory slab(float thickness_mm, MaterialTable table, float ior) {
    return [=] {
        int nz = std::max(1, int(std::lround(thickness_mm / 0.1f)));
        return boxScene({20, 20, nz}, {0.1f, 0.1f, thickness_mm / nz}, [](const Vec3i&) { return kA; }, table, ior);
    };
}

// A slab thinner than a voxel, centred in one 0.1 mm layer of voxels.
SceneFactory subVoxelSlab(float thickness_mm, MaterialTable table, float ior) {
    return [=] {
        LabelGrid grid = labelGrid({20, 20, 1}, {0.1f, 0.1f, 0.1f}, [](const Vec3i&) { return kA; });
        float z0 = 0.05f - thickness_mm / 2;
        return sceneOf(boxMesh({0, 0, z0}, {2, 2, z0 + thickness_mm}), std::move(grid), table, ior);
    };
}

// Clear resin (x < 1 mm) beside white (x >= 1 mm) in a 2 mm cube.
SceneFactory contrastCube(double clearAlbedo, double whiteAlbedo, float ior) {
    MaterialTable t = tableOf({{kA, material(gray(1e-6), gray(clearAlbedo))},
                               {kB, material(gray(24), gray(whiteAlbedo))}});
    return [=] {
        return boxScene({20, 20, 20}, {0.1f, 0.1f, 0.1f}, [](const Vec3i& v) { return v.x < 10 ? kA : kB; }, t, ior);
    };
}

// A 2-degree wedge, 4 mm long, 2 mm deep, in 0.05 mm voxels.
constexpr float kWedgeLength = 4, kWedgeDepth = 2;
const float kWedgeSlope = std::tan(2.0f * kPi / 180.0f);
SceneFactory wedge(MaterialTable table, float ior) {
    return [=] {
        float h = kWedgeLength * kWedgeSlope;
        Vec3i res{80, 40, std::max(1, int(std::ceil(h / 0.05f)))};
        LabelGrid grid = labelGrid(res, {0.05f, 0.05f, 0.05f}, [](const Vec3i&) { return kA; });
        return sceneOf(wedgeMesh({0, 0, 0}, kWedgeLength, h, kWedgeDepth), std::move(grid), table, ior);
    };
}

// ---- sensors ------------------------------------------------------------

std::unique_ptr<Sensor> surfaceSensor(const Scene& s) {
    const LabelGrid& g = s.medium->grid();
    return std::make_unique<SurfaceVoxelSensor>(*s.geometry, g.frame(), g.surfaceVoxels());
}

// Orthographic, looking down -z from above (x, y), view width x height mm.
SensorFactory topCamera(float x, float y, float viewWidth_mm, int width, int height, float zAbove = 30) {
    return [=](const Scene& s) {
        Vec3f o = s.worldOrigin_mm;
        CameraPose pose{Point3f{x, y, zAbove} - o, Point3f{x, y, zAbove - 1} - o, {0, 1, 0}};
        return std::make_unique<OrthographicSensor>(pose, viewWidth_mm, width, height);
    };
}

// Rays through a `size` mm cube at `corner` in voxels of `voxel` mm, along
// -z, -x and -y: on voxel edges (where four voxels meet) and on voxel faces.
SensorFactory axisRays(float size, float voxel, Point3f corner) {
    return [=](const Scene& s) {
        std::vector<Ray> rays;
        int n = int(std::lround(size / voxel));
        for (int axis = 0; axis < 3; ++axis)
            for (int i = 1; i < n; ++i)
                for (int j = 1; j < n; ++j)
                    for (float shift : {0.0f, 0.5f}) {
                        float a = i * voxel, b = (j + shift) * voxel;
                        Point3f o = corner;
                        Vec3f d{0, 0, 0};
                        o[axis] += size + 1;
                        o[(axis + 1) % 3] += a;
                        o[(axis + 2) % 3] += b;
                        d[axis] = -1;
                        rays.push_back({o - s.worldOrigin_mm, d});
                    }
        return std::make_unique<FixedRaySensor>(std::move(rays));
    };
}

// ---- cases --------------------------------------------------------------

double fresnelNormal(double ior) { return std::pow((ior - 1) / (ior + 1), 2); }

// Slab at normal incidence under a uniform environment: what the camera sees
// is the slab's reflectance plus its transmittance (interreflections summed).
double slabSeenAtNormal(double ior, double transmittance) {
    double f = fresnelNormal(ior), t2 = transmittance * transmittance;
    double reflect = f + (1 - f) * (1 - f) * f * t2 / (1 - f * f * t2);
    double transmit = (1 - f) * (1 - f) * transmittance / (1 - f * f * t2);
    return reflect + transmit;
}

std::vector<Case> allCases() {
    std::vector<Case> cs;
    const std::string furnace = "furnace (albedo 1, environment 1)";
    auto value = [&](std::string name, std::string params, SceneFactory scene, SensorFactory sensor, double expected,
                     std::string source, uint32_t spp, bool quick) {
        Case c(std::move(name), std::move(params), std::move(scene), std::move(sensor));
        c.expected = expected;
        c.source = std::move(source);
        c.spp = spp;
        c.quick = quick;
        cs.push_back(std::move(c));
    };
    auto other = [&](std::string name, std::string params, SceneFactory scene, SensorFactory sensor, uint32_t spp,
                     bool quick) {
        Case c(std::move(name), std::move(params), std::move(scene), std::move(sensor));
        c.expect = Expect::OtherEstimator;
        c.source = "the other estimator";
        c.spp = spp;
        c.quick = quick;
        cs.push_back(std::move(c));
    };
    SensorFactory surface = surfaceSensor;
    const Point3f far{1000, 1000, 1000};

    // Index of refraction.
    for (double ior : {1.0, 1.5, 2.5}) {
        char p[96];
        std::snprintf(p, sizeof p, "2 mm cube, sigma_t 24/mm, g 0, IOR %.1f", ior);
        value("furnace IOR " + std::to_string(ior).substr(0, 3), std::string(p) + ", albedo 1",
              cube(2, 0.1f, oneMaterial(24, 1), float(ior)), surface, 1.0, furnace, 4, ior == 1.5);
        value("albedo 0 IOR " + std::to_string(ior).substr(0, 3), std::string(p) + ", albedo 0",
              cube(2, 0.1f, oneMaterial(24, 0), float(ior)), surface, fresnelNormal(ior),
              "closed form: Fresnel reflectance at normal incidence ((n-1)/(n+1))^2 (transmission e^-48)", 16,
              ior == 2.5);
        other("IOR " + std::to_string(ior).substr(0, 3), "2 mm cube, sigma_t 10/mm, albedo 0.9, IOR " +
              std::to_string(ior).substr(0, 3), cube(2, 0.1f, oneMaterial(10, 0.9), float(ior)), surface, 16, ior == 2.5);
    }
    // Phase function asymmetry.
    for (double g : {-0.99, 0.0, 0.99}) {
        std::string gs = g == 0 ? "0" : (g < 0 ? "-0.99" : "0.99");
        other("g " + gs, "2 mm cube, sigma_t 24/mm, albedo 0.99, IOR 1.5, g " + gs,
              cube(2, 0.1f, oneMaterial(24, 0.99, g), 1.5f), surface, 8, g == 0.99);
        if (g != 0)
            value("furnace g " + gs, "2 mm cube, sigma_t 24/mm, albedo 1, IOR 1.5, g " + gs,
                  cube(2, 0.1f, oneMaterial(24, 1, g), 1.5f), surface, 1.0, furnace, 2, false);
    }
    // Long paths: albedo exactly 1 in a 20 mm cube, no depth cap.
    value("furnace 20 mm cube", "20 mm cube (0.5 mm voxels), sigma_t 24/mm, albedo 1, IOR 1.5, no depth cap; 8x8 px on the top face",
          cube(20, 0.5f, oneMaterial(24, 1), 1.5f), topCamera(10, 10, 4, 8, 8), 1.0, furnace, 4, true);
    // Majorant contrast 1e7 inside one brick.
    value("contrast furnace", "2 mm cube: clear 1e-6/mm (x < 1) beside white 24/mm, albedo 1, IOR 1.5",
          contrastCube(1, 1, 1.5f), surface, 1.0, furnace, 4, true);
    value("contrast Beer-Lambert", "as above, albedo 0, IOR 1; 8x8 px looking through 2 mm of the clear half",
          contrastCube(0, 0, 1.0f), topCamera(0.5f, 1, 0.8f, 8, 8), std::exp(-2e-6),
          "Beer-Lambert exp(-1e-6 * 2)", 64, true);
    other("contrast", "2 mm cube: clear 1e-6/mm (albedo 1) beside white 24/mm (albedo 0.95), IOR 1.5",
          contrastCube(1, 0.95, 1.5f), surface, 8, false);
    // Many events per voxel.
    value("dense furnace", "0.2 mm cube (0.025 mm voxels), sigma_t 1e4/mm, albedo 1, IOR 1.5",
          cube(0.2f, 0.025f, oneMaterial(1e4, 1), 1.5f), surface, 1.0, furnace, 1, false);
    value("dense Beer-Lambert", "0.0003 mm slab (in a 0.1 mm voxel layer), sigma_t 1e4/mm, albedo 0, IOR 1",
          subVoxelSlab(0.0003f, oneMaterial(1e4, 0), 1.0f), topCamera(1, 1, 1, 8, 8), std::exp(-3.0),
          "Beer-Lambert exp(-1e4 * 0.0003)", 256, true);
    other("dense", "0.4 mm cube (0.05 mm voxels), sigma_t 1e4/mm, albedo 0.95, IOR 1.5",
          cube(0.4f, 0.05f, oneMaterial(1e4, 0.95), 1.5f), surface, 16, true);
    // Slabs, down to thinner than a voxel.
    value("slab Beer-Lambert", "2x2x1 mm slab, sigma_t 1/mm, albedo 0, IOR 1; 8x8 px looking through it",
          slab(1, oneMaterial(1, 0), 1.0f), topCamera(1, 1, 1, 8, 8), std::exp(-1.0), "Beer-Lambert exp(-1)", 256, true);
    value("slab Beer-Lambert + Fresnel", "as above, IOR 1.5", slab(1, oneMaterial(1, 0), 1.5f), topCamera(1, 1, 1, 8, 8),
          slabSeenAtNormal(1.5, std::exp(-1.0)), "closed form: slab reflectance + transmittance at normal incidence", 256, false);
    value("sub-voxel slab", "0.03 mm slab inside one 0.1 mm voxel layer, sigma_t 24/mm, albedo 0, IOR 1",
          subVoxelSlab(0.03f, oneMaterial(24, 0), 1.0f), topCamera(1, 1, 1, 8, 8), std::exp(-24 * 0.03),
          "Beer-Lambert exp(-24 * 0.03)", 256, true);
    value("sub-voxel slab furnace", "as above, albedo 1, IOR 1.5", subVoxelSlab(0.03f, oneMaterial(24, 1), 1.5f),
          topCamera(1, 1, 1, 8, 8), 1.0, furnace, 64, false);
    // A sharp wedge (2 degrees), looked at from above over its first 2 mm.
    {
        float w = 2;
        double a = 24 * double(kWedgeSlope);
        value("wedge Beer-Lambert", "2-degree wedge, sigma_t 24/mm, albedo 0, IOR 1; 16x8 px over x in [0, 2] mm",
              wedge(oneMaterial(24, 0), 1.0f), topCamera(w / 2, kWedgeDepth / 2, w, 16, 8),
              (1 - std::exp(-a * w)) / (a * w), "Beer-Lambert averaged over the wedge: (1 - e^-aw)/(aw), a = 24 tan 2 deg", 64,
              true);
        value("wedge furnace", "as above, albedo 1, IOR 1.5", wedge(oneMaterial(24, 1), 1.5f),
              topCamera(w / 2, kWedgeDepth / 2, w, 16, 8), 1.0, furnace, 16, false);
        other("wedge", "as above, albedo 0.9, IOR 1.5", wedge(oneMaterial(24, 0.9), 1.5f),
              topCamera(w / 2, kWedgeDepth / 2, w, 16, 8), 64, false);
        // Where the wedge is thinner than the ray offset (1e-4 mm, x < 0.003 mm:
        // 0.14 % of these rays) the far face lies within a spawned ray's tMin,
        // so the ray finds no boundary; it counts as a leak and leaves, as
        // light through a film that thin would. Budget: four times that share.
        for (size_t i = cs.size() - 3; i < cs.size(); ++i) cs[i].maxLeakFraction = 4 * 1e-4 / (double(kWedgeSlope) * w);
    }
    // Rays exactly along the grid axes, on voxel faces and edges.
    value("axis rays", "1 mm cube (0.1 mm voxels), sigma_t 2/mm, albedo 0, IOR 1; 486 rays along -x, -y, -z on voxel edges and faces",
          cube(1, 0.1f, oneMaterial(2, 0), 1.0f), axisRays(1, 0.1f, {0, 0, 0}), std::exp(-2.0), "Beer-Lambert exp(-2)", 64,
          true);
    // Far from the origin: 1 m offset (float spacing ~6e-5 mm there).
    value("far axis rays", "as above, the cube's corner at (1000, 1000, 1000) mm",
          cube(1, 0.1f, oneMaterial(2, 0), 1.0f, far), axisRays(1, 0.1f, far), std::exp(-2.0), "Beer-Lambert exp(-2)", 64,
          true);
    value("far furnace", "2 mm cube at (1000, 1000, 1000) mm, sigma_t 24/mm, albedo 1, IOR 1.5",
          cube(2, 0.1f, oneMaterial(24, 1), 1.5f, far), surface, 1.0, furnace, 4, true);
    {
        Case c("far from origin", "2 mm cube at (1000, 1000, 1000) mm, sigma_t 24/mm, albedo 0.9, IOR 1.5",
               cube(2, 0.1f, oneMaterial(24, 0.9), 1.5f, far), surface);
        c.expect = Expect::SameSceneAtOrigin;
        c.source = "the same cube at the origin (another seed)";
        c.spp = 16;
        c.quick = true;
        c.originScene = cube(2, 0.1f, oneMaterial(24, 0.9), 1.5f);
        cs.push_back(std::move(c));
    }
    return cs;
}

// Labels missing from the material table must stop the load with a clear
// error (files written to a temporary directory, read by loadScene).
StabilityRow missingLabelRow() {
    namespace fs = std::filesystem;
    StabilityRow row;
    row.caseName = "labels missing from the material table";
    row.parameters = "grid with labels 1 and 7; table defines 1 only";
    row.estimator = "load";
    row.source = "input check: one-line error naming the label";
    fs::path dir = fs::temp_directory_path() / ("printlight_stability_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    writeObj(boxMesh({0, 0, 0}, {1, 1, 1}), dir / "cube.obj");
    writeLabelGridBin(labelGrid({10, 10, 10}, {0.1f, 0.1f, 0.1f}, [](const Vec3i& v) { return v.x < 5 ? kA : Label(7); }),
                      dir / "grid.bin");
    std::ofstream(dir / "materials.json") << R"({"materials": [{"label": 1, "name": "white", "density": 24, "albedo": 0.99, "anisotropy": 0}]})";
    std::ofstream(dir / "scene.json") << R"({"object": {"mesh": "cube.obj", "labels": "grid.bin", "materials": "materials.json"},
                                                  "sensor": {"type": "surface_voxels"}})";
    try {
        loadScene(parseScene(dir / "scene.json"));
        row.note = "loaded without an error";
    } catch (const InputError& e) {
        std::string msg = e.what();
        row.pass = msg.find("label 7") != std::string::npos && msg.find('\n') == std::string::npos;
        size_t at = msg.find("grid.bin");  // drop the temporary directory
        row.note = "error: " + (at == std::string::npos ? msg : msg.substr(at));
    } catch (const std::exception& e) {
        row.note = std::string("unexpected error: ") + e.what();
    }
    fs::remove_all(dir);
    return row;
}

}  // namespace

std::vector<StabilityRow> runStabilitySuite(bool quick, uint64_t seed,
                                            const std::function<void(const StabilityRow&)>& progress) {
    std::vector<StabilityRow> rows;
    for (const Case& c : allCases()) {
        if (quick && !c.quick) continue;
        uint32_t spp = quick ? std::max(1u, c.spp / 2) : 8 * c.spp;
        Scene scene = c.scene();
        std::unique_ptr<Sensor> sensor = c.sensor(scene);
        Measurement m[2];
        const char* estimators[2] = {"volpath", "printpt"};
        for (int e = 0; e < 2; ++e) m[e] = measure(scene, *sensor, estimators[e], spp, seed);
        Measurement origin[2];
        if (c.expect == Expect::SameSceneAtOrigin) {
            Scene o = c.originScene();
            std::unique_ptr<Sensor> os = c.sensor(o);
            for (int e = 0; e < 2; ++e) origin[e] = measure(o, *os, estimators[e], spp, seed + 7919);
        }
        for (int e = 0; e < 2; ++e) {
            StabilityRow row;
            row.caseName = c.name;
            row.parameters = c.parameters;
            row.estimator = estimators[e];
            row.source = c.source;
            row.measured = m[e].mean;
            row.stdErr = m[e].stdErr;
            row.nonFinite = m[e].nonFinite;
            row.paths = m[e].stats.paths;
            row.leaks = m[e].stats.leaks;
            row.trapped = m[e].stats.trapped;
            row.seconds = m[e].seconds;
            row.maxLeakFraction = c.maxLeakFraction;
            if (c.expect == Expect::Value) {
                row.expected = c.expected;
            } else {
                const Measurement& ref = c.expect == Expect::OtherEstimator ? m[1 - e] : origin[e];
                row.expected = ref.mean;
                row.expectedStdErr = ref.stdErr;
            }
            judge(row);
            progress(row);
            rows.push_back(row);
        }
    }
    rows.push_back(missingLabelRow());
    progress(rows.back());
    return rows;
}

}  // namespace pl
