// printlight info: what a label grid holds and what it costs in memory.
#include <cstdio>

#include "apps/arguments.h"
#include "apps/command_options.h"
#include "io/grid_io.h"
#include "media/materials.h"

namespace pl {

int infoCommand(const std::vector<std::string>& argv) {
    Arguments args("info", argv, {{"--void-label", "N", "the label of empty space (0..255)"}});
    if (args.positional().size() != 1) throw UsageError("info needs exactly one VOLUME");
    std::optional<Label> voidLabel;
    if (auto v = args.integer("--void-label", 0, 255)) voidLabel = Label(*v);
    const std::string file = args.positional()[0];
    LabelGrid grid = loadLabelGrid(file, voidLabel);
    const GridFrame& f = grid.frame();
    Point3f hi = f.cornerMax_mm();
    uint64_t n = f.voxelCount();

    std::printf("file:        %s\n", file.c_str());
    std::printf("resolution:  %d x %d x %d = %llu voxels\n", f.resolution.x, f.resolution.y,
                f.resolution.z, (unsigned long long)n);
    std::printf("voxel size:  %.6g x %.6g x %.6g mm\n", f.voxelSize_mm.x, f.voxelSize_mm.y, f.voxelSize_mm.z);
    std::printf("bounds:      [%.4f, %.4f, %.4f] - [%.4f, %.4f, %.4f] mm (%.3f x %.3f x %.3f mm)\n",
                f.cornerMin_mm.x, f.cornerMin_mm.y, f.cornerMin_mm.z, hi.x, hi.y, hi.z,
                hi.x - f.cornerMin_mm.x, hi.y - f.cornerMin_mm.y, hi.z - f.cornerMin_mm.z);
    std::printf("index box:   [%d, %d, %d] - [%d, %d, %d]\n", f.indexMin.x, f.indexMin.y,
                f.indexMin.z, f.indexMax().x - 1, f.indexMax().y - 1, f.indexMax().z - 1);
    std::printf("void label:  %d\n", grid.voidLabel());
    std::printf("labels:\n  %5s  %-12s %14s %9s\n", "label", "convention", "voxels", "share");
    auto hist = grid.histogram();
    for (int l = 0; l < 256; ++l)
        if (hist[size_t(l)])
            std::printf("  %5d  %-12s %14llu %8.3f%%\n", l, researchLabelName(l),
                        (unsigned long long)hist[size_t(l)], 100.0 * double(hist[size_t(l)]) / double(n));
    double sparse = double(grid.memoryBytes());
    double dense = double(n) * 16.0;  // float albedo RGB + float density per voxel (Brecka table 3.2)
    std::printf("memory:      sparse 8-bit tree %.2f MB; dense float grid (albedo RGB + density, "
                "16 B/voxel) %.2f MB; ratio x%.1f\n",
                sparse / 1e6, dense / 1e6, dense / sparse);
    return 0;
}

}  // namespace pl
