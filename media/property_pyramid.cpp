#include "media/property_pyramid.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "runtime/scheduler.h"

namespace pl {

namespace {

void accumulate(CellProperties& sum, const CellProperties& add, float weight) {
    sum.filled += weight * add.filled;
    for (int c = 0; c < 3; ++c) {
        sum.sigmaS_perMm[c] += weight * add.sigmaS_perMm[c];
        sum.sigmaA_perMm[c] += weight * add.sigmaA_perMm[c];
    }
}

}  // namespace

PropertyPyramid::PropertyPyramid(const LabelMedium& medium, float baseCell_mm, int levels, uint64_t maxBytes) {
    const GridFrame& frame = medium.frame();
    for (int a = 0; a < 3; ++a)
        if (frame.voxelSize_mm[a] > baseCell_mm)
            throw std::invalid_argument("voxels larger than the descriptor's finest cell (" +
                                        std::to_string(baseCell_mm) + " mm)");
    origin_mm_ = frame.cornerMin_mm;
    const Vec3f extent_mm = frame.cornerMax_mm() - frame.cornerMin_mm;
    uint64_t bytes = 0;
    for (int l = 0; l < levels; ++l) {
        Level level;
        level.cell_mm = baseCell_mm * float(1 << l);
        for (int a = 0; a < 3; ++a) level.size[a] = std::max(1, int(std::ceil(extent_mm[a] / level.cell_mm)));
        bytes += uint64_t(level.size.x) * uint64_t(level.size.y) * uint64_t(level.size.z) * sizeof(CellProperties);
        levels_.push_back(level);
    }
    if (bytes > maxBytes)
        throw std::length_error("the descriptor's property pyramid would take " + std::to_string(bytes >> 20) +
                                " MiB (limit " + std::to_string(maxBytes >> 20) + " MiB)");

    // Per label: the coefficients of each channel.
    std::array<CellProperties, 256> ofLabel{};
    const Label voidLabel = medium.grid().voidLabel();
    for (int l = 0; l < 256; ++l) {
        if (l == voidLabel) continue;
        ofLabel[size_t(l)].filled = 1;
        for (int c = 0; c < 3; ++c) {
            const ChannelLut& lut = medium.lut(c);
            ofLabel[size_t(l)].sigmaS_perMm[c] = lut.sigmaT_perMm[l] * lut.albedo[l];
            ofLabel[size_t(l)].sigmaA_perMm[c] = lut.sigmaT_perMm[l] * (1 - lut.albedo[l]);
        }
    }

    // The finest level: the mean over the voxels whose centres fall in each
    // cell (void voxels included). One z-slab of cells per task.
    Level& base = levels_[0];
    base.cells.assign(size_t(base.size.x) * size_t(base.size.y) * size_t(base.size.z), CellProperties{});
    auto cellOf = [&](int voxel, int axis) {
        const float centre_mm = (float(voxel) + 0.5f) * frame.voxelSize_mm[axis];
        return std::min(base.size[axis] - 1, int(centre_mm / base.cell_mm));
    };
    std::vector<int> cellX(size_t(frame.resolution.x)), cellY(size_t(frame.resolution.y));
    for (int x = 0; x < frame.resolution.x; ++x) cellX[size_t(x)] = cellOf(x, 0);
    for (int y = 0; y < frame.resolution.y; ++y) cellY[size_t(y)] = cellOf(y, 1);
    std::vector<int> firstVoxelZ(size_t(base.size.z) + 1, frame.resolution.z);
    for (int z = frame.resolution.z - 1; z >= 0; --z) firstVoxelZ[size_t(cellOf(z, 2))] = z;
    for (int cz = base.size.z - 1; cz >= 0; --cz)
        firstVoxelZ[size_t(cz)] = std::min(firstVoxelZ[size_t(cz)], firstVoxelZ[size_t(cz) + 1]);
    parallelForTiles(size_t(base.size.z), 1, [&](size_t begin, size_t end) {
        LabelMedium::Tracker sampler(medium);
        const size_t slab = size_t(base.size.x) * size_t(base.size.y);
        std::vector<uint32_t> count(slab);
        for (size_t cz = begin; cz < end; ++cz) {
            std::fill(count.begin(), count.end(), 0u);
            CellProperties* cells = &base.cells[cz * slab];
            for (int z = firstVoxelZ[cz]; z < firstVoxelZ[cz + 1]; ++z)
                for (int y = 0; y < frame.resolution.y; ++y)
                    for (int x = 0; x < frame.resolution.x; ++x) {
                        const size_t cell = size_t(cellY[size_t(y)]) * size_t(base.size.x) + size_t(cellX[size_t(x)]);
                        const Label label =
                            sampler.labelAt({frame.indexMin.x + x, frame.indexMin.y + y, frame.indexMin.z + z});
                        accumulate(cells[cell], ofLabel[label], 1.0f);
                        ++count[cell];
                    }
            for (size_t k = 0; k < slab; ++k)
                if (count[k] > 0) {
                    CellProperties mean;
                    accumulate(mean, cells[k], 1.0f / float(count[k]));
                    cells[k] = mean;
                }
        }
    });

    // Coarser levels: the mean of the eight children (beyond the grid: void).
    for (size_t l = 1; l < levels_.size(); ++l) {
        const Level& fine = levels_[l - 1];
        Level& coarse = levels_[l];
        coarse.cells.assign(size_t(coarse.size.x) * size_t(coarse.size.y) * size_t(coarse.size.z), CellProperties{});
        parallelForTiles(size_t(coarse.size.z), 1, [&](size_t begin, size_t end) {
            for (int z = int(begin); z < int(end); ++z)
                for (int y = 0; y < coarse.size.y; ++y)
                    for (int x = 0; x < coarse.size.x; ++x) {
                        CellProperties& mean = coarse.cells[(size_t(z) * size_t(coarse.size.y) + size_t(y)) *
                                                                size_t(coarse.size.x) + size_t(x)];
                        for (int k = 0; k < 8; ++k)
                            if (const CellProperties* child = fine.cell(2 * x + (k & 1), 2 * y + ((k >> 1) & 1),
                                                                        2 * z + (k >> 2)))
                                accumulate(mean, *child, 0.125f);
                    }
        });
    }
}

CellProperties PropertyPyramid::at(int level, const Point3f& p_mm) const {
    const Level& l = levels_[size_t(level)];
    float u[3], f[3];
    int i[3];
    for (int a = 0; a < 3; ++a) {
        u[a] = (p_mm[a] - origin_mm_[a]) / l.cell_mm - 0.5f;
        i[a] = int(std::floor(u[a]));
        f[a] = u[a] - float(i[a]);
    }
    CellProperties sum;
    for (int k = 0; k < 8; ++k) {
        const int dx = k & 1, dy = (k >> 1) & 1, dz = k >> 2;
        const CellProperties* cell = l.cell(i[0] + dx, i[1] + dy, i[2] + dz);
        if (!cell) continue;
        const float w = (dx ? f[0] : 1 - f[0]) * (dy ? f[1] : 1 - f[1]) * (dz ? f[2] : 1 - f[2]);
        accumulate(sum, *cell, w);
    }
    return sum;
}

uint64_t PropertyPyramid::memoryBytes() const {
    uint64_t bytes = 0;
    for (const Level& l : levels_) bytes += l.cells.size() * sizeof(CellProperties);
    return bytes;
}

}  // namespace pl
