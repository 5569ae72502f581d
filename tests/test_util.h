// Shared helpers for the tests: synthetic box scenes and statistics.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <functional>
#include <string>
#include <vector>

#include "core/geometry.h"
#include "integrators/scene.h"
#include "media/label_grid.h"
#include "media/materials.h"

namespace pl::test {

// Axis-aligned box with outward counter-clockwise winding.
inline TriangleMesh boxMesh(const Point3f& lo, const Point3f& hi) {
    TriangleMesh m;
    for (int i = 0; i < 8; ++i)
        m.positions_mm.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    // Faces as quads (a,b,c,d) counter-clockwise from outside.
    const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                  {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) m.indices.insert(m.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
    return m;
}

inline MaterialTable tableOf(std::initializer_list<std::pair<Label, Material>> entries) {
    MaterialTable t;
    for (const auto& [label, m] : entries) {
        t.byLabel[label] = m;
        t.byLabel[label].defined = true;
    }
    return t;
}

inline Material material(RGB sigmaT, RGB albedo, RGB g = {0, 0, 0}) {
    Material m;
    m.sigmaT_perMm = sigmaT;
    m.albedo = albedo;
    m.g = g;
    m.defined = true;
    return m;
}

constexpr Label kTestVoid = 5;

// Box [0, size] whose voxels (voxel_mm, fitting exactly) carry labelOf(voxel).
inline LabelGrid boxGrid(const Vec3i& resolution, const Vec3f& voxel_mm,
                         const std::function<Label(const Vec3i&)>& labelOf) {
    GridFrame f;
    f.resolution = resolution;
    f.voxelSize_mm = voxel_mm;
    std::vector<Label> labels(f.voxelCount());
    size_t i = 0;
    for (int z = 0; z < resolution.z; ++z)
        for (int y = 0; y < resolution.y; ++y)
            for (int x = 0; x < resolution.x; ++x) labels[i++] = labelOf({x, y, z});
    return LabelGrid::fromDense(f, labels, kTestVoid);
}

inline Scene boxScene(const Vec3i& resolution, const Vec3f& voxel_mm,
                      const std::function<Label(const Vec3i&)>& labelOf, MaterialTable table,
                      float ior, RGB environment = {1, 1, 1}) {
    Scene s;
    Point3f hi{resolution.x * voxel_mm.x, resolution.y * voxel_mm.y, resolution.z * voxel_mm.z};
    s.geometry = std::make_unique<Geometry>(boxMesh({0, 0, 0}, hi));
    s.medium = std::make_unique<LabelMedium>(boxGrid(resolution, voxel_mm, labelOf), std::move(table));
    s.ior = ior;
    s.environment = environment;
    s.clearance = std::make_unique<SurfaceClearance>(*s.geometry, s.medium->frame());
    return s;
}

// Pearson chi-square test; bins with small expectation are pooled. Returns
// the Wilson-Hilferty z-score of the statistic (about N(0,1) under H0).
inline double chiSquareZ(const std::vector<double>& observed, const std::vector<double>& expected) {
    double chi2 = 0, poolO = 0, poolE = 0;
    int bins = 0;
    for (size_t i = 0; i < observed.size(); ++i) {
        poolO += observed[i];
        poolE += expected[i];
        if (poolE >= 20) {
            chi2 += (poolO - poolE) * (poolO - poolE) / poolE;
            ++bins;
            poolO = poolE = 0;
        }
    }
    if (poolE > 0) {
        chi2 += (poolO - poolE) * (poolO - poolE) / std::max(poolE, 1e-9);
        ++bins;
    }
    double k = std::max(1, bins - 1);
    return (std::cbrt(chi2 / k) - (1 - 2 / (9 * k))) / std::sqrt(2 / (9 * k));
}

// z below this: no evidence against the distribution (one-sided p ~ 1e-5).
constexpr double kChiSquareZLimit = 4.3;

inline std::filesystem::path freshTempDir(const std::string& name) {
    // Per process: ctest runs test cases in parallel processes.
    auto dir = std::filesystem::temp_directory_path() /
               ("printlight_test_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

inline std::filesystem::path sourceDir() { return PRINTLIGHT_SOURCE_DIR; }

inline std::string readText(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

inline int countOf(const std::string& text, const std::string& needle) {
    int n = 0;
    for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + needle.size())) ++n;
    return n;
}

#ifdef PRINTLIGHT_EXE
struct CliRun {
    int exitCode;
    std::string out, err;
};

// Runs the printlight program with its output captured in files in dir.
inline CliRun runPrintlight(const std::string& args, const std::filesystem::path& dir) {
    std::string cmd = std::string(PRINTLIGHT_EXE) + " " + args + " >" + (dir / "stdout.txt").string() +
                      " 2>" + (dir / "stderr.txt").string();
    int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, readText(dir / "stdout.txt"),
            readText(dir / "stderr.txt")};
}
#endif

}  // namespace pl::test
