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
#include "scene/scene.h"
#include "testing/synthetic_scene.h"
#include "media/label_grid.h"
#include "media/materials.h"

namespace pl::test {

using synthetic::boxMesh;
using synthetic::boxScene;
using synthetic::material;
using synthetic::tableOf;
constexpr Label kTestVoid = synthetic::kVoid;

// The halftone-like resins the estimator tests mix: two inks (labels 0
// and 1), a black (3), a white (4) and a nearly clear resin (6).
inline MaterialTable mixedResins() {
    return tableOf({{0, material({10, 8, 8}, {0.25f, 0.97f, 0.99f}, {0.4f, 0.4f, 0.4f})},
                    {1, material({2.5f, 10, 6}, {0.98f, 0.25f, 0.9f}, {0.4f, 0.4f, 0.4f})},
                    {3, material({20, 20, 20}, {0.02f, 0.02f, 0.02f}, {0.4f, 0.4f, 0.4f})},
                    {4, material({6, 9, 24}, {0.995f, 0.995f, 0.995f}, {0.4f, 0.4f, 0.4f})},
                    {6, material({1e-4f, 1e-4f, 1e-4f}, {1, 1, 1})}});
}

// Box [0, size] whose voxels (voxel_mm, fitting exactly) carry labelOf(voxel).
inline LabelGrid boxGrid(const Vec3i& resolution, const Vec3f& voxel_mm,
                         const std::function<Label(const Vec3i&)>& labelOf) {
    return synthetic::labelGrid(resolution, voxel_mm, labelOf);
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

// The folders freshTempDir made, removed when the test process ends.
class TempDirs {
public:
    ~TempDirs() {
        std::error_code ignored;
        for (const auto& dir : dirs_) std::filesystem::remove_all(dir, ignored);
    }
    void add(const std::filesystem::path& dir) { dirs_.push_back(dir); }

private:
    std::vector<std::filesystem::path> dirs_;
};
inline TempDirs& tempDirs() {
    static TempDirs dirs;
    return dirs;
}

// An empty folder in the system's temporary directory, removed at exit.
inline std::filesystem::path freshTempDir(const std::string& name) {
    // Per process: ctest runs test cases in parallel processes.
    auto dir = std::filesystem::temp_directory_path() /
               ("printlight_test_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    tempDirs().add(dir);
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
    // Its own cache folder (the printer's characterisation), inside the test's.
    std::string cmd = "XDG_CACHE_HOME=" + (dir / "cache").string() + " " + std::string(PRINTLIGHT_EXE) + " " + args +
                      " >" + (dir / "stdout.txt").string() +
                      " 2>" + (dir / "stderr.txt").string();
    int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, readText(dir / "stdout.txt"),
            readText(dir / "stderr.txt")};
}
#endif

}  // namespace pl::test
