// make-test-data OUTDIR: writes the bundled 10 mm cube label grids
// (until `printlight prepare` exists). Deterministic: same files every run.
//   cube10_white.vdb    every voxel touching the cube is white resin
//   cube10_pattern.vdb  a high-frequency 0.5 mm checker of C/M/Y/K/W in the
//                       outer 1 mm (extruded inward from the nearest face),
//                       white inside
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "io/grid_io.h"

namespace {

using namespace pl;

constexpr Label kCyan = 0, kMagenta = 1, kYellow = 2, kBlack = 3, kWhite = 4, kAir = 5;
constexpr float kCube_mm = 10.0f;
constexpr float kShell_mm = 1.0f;
constexpr float kChecker_mm = 0.5f;
const Vec3f kPrinterVoxel_mm{0.0423f, 0.0847f, 0.027f};  // 600 x 300 dpi, 27 um layers

GridFrame cubeFrame() {
    GridFrame f;
    f.voxelSize_mm = kPrinterVoxel_mm;
    for (int a = 0; a < 3; ++a) {
        // Two voxels of void padding on every side.
        f.resolution[a] = int(std::ceil(kCube_mm / kPrinterVoxel_mm[a])) + 4;
        f.cornerMin_mm[a] = -2.0f * kPrinterVoxel_mm[a];
    }
    return f;
}

// Pattern label of a shell voxel, from the face nearest to its centre.
Label patternLabel(const Point3f& c) {
    float best = 1e30f;
    int axis = 0;
    bool high = false;
    for (int a = 0; a < 3; ++a) {
        float dLo = c[a], dHi = kCube_mm - c[a];
        if (dLo < best) { best = dLo; axis = a; high = false; }
        if (dHi < best) { best = dHi; axis = a; high = true; }
    }
    if (best > kShell_mm) return kWhite;
    int u = int(std::floor(c[(axis + 1) % 3] / kChecker_mm));
    int v = int(std::floor(c[(axis + 2) % 3] / kChecker_mm));
    static const Label palette[5] = {kCyan, kMagenta, kYellow, kBlack, kWhite};
    uint32_t h = uint32_t(u * 73856093) ^ uint32_t(v * 19349663) ^ uint32_t((2 * axis + high) * 83492791);
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    return palette[h % 5];
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: make-test-data OUTDIR\n");
        return 2;
    }
    std::filesystem::path dir = argv[1];
    GridFrame f = cubeFrame();
    std::vector<Label> white(f.voxelCount()), pattern(f.voxelCount());
    size_t i = 0;
    for (int z = 0; z < f.resolution.z; ++z)
        for (int y = 0; y < f.resolution.y; ++y)
            for (int x = 0; x < f.resolution.x; ++x, ++i) {
                Vec3i v{x, y, z};
                // A voxel belongs to the object if it overlaps the cube.
                bool inside = true;
                for (int a = 0; a < 3; ++a) {
                    float lo = f.cornerMin_mm[a] + v[a] * f.voxelSize_mm[a];
                    inside = inside && lo + f.voxelSize_mm[a] > 0.0f && lo < kCube_mm;
                }
                white[i] = inside ? kWhite : kAir;
                pattern[i] = inside ? patternLabel(f.voxelCenter_mm(v)) : kAir;
            }
    try {
        writeLabelGridVdb(LabelGrid::fromDense(f, white, kAir), dir / "cube10_white.vdb");
        writeLabelGridVdb(LabelGrid::fromDense(f, pattern, kAir), dir / "cube10_pattern.vdb");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "make-test-data: error: %s\n", e.what());
        return 1;
    }
    std::printf("make-test-data: wrote cube10_white.vdb and cube10_pattern.vdb to %s\n", dir.string().c_str());
    return 0;
}
