#include "media/label_grid.h"

#include <algorithm>
#include <mutex>
#include <stdexcept>
#include <string>

#include "media/label_tree.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

namespace pl {

void initializeVdb() {
    static std::once_flag once;
    std::call_once(once, [] {
        openvdb::initialize();
        if (!LabelVdbGrid::isRegistered()) LabelVdbGrid::registerGrid();
    });
}

LabelGrid::LabelGrid() = default;
LabelGrid::LabelGrid(GridFrame frame, Label voidLabel, std::shared_ptr<Tree> tree)
    : frame_(frame), voidLabel_(voidLabel), tree_(std::move(tree)) {}
LabelGrid::~LabelGrid() = default;
LabelGrid::LabelGrid(LabelGrid&&) noexcept = default;
LabelGrid& LabelGrid::operator=(LabelGrid&&) noexcept = default;

LabelGrid LabelGrid::fromDense(const GridFrame& frame, const std::vector<Label>& labels,
                               Label voidLabel) {
    initializeVdb();
    auto tree = std::make_shared<Tree>();
    tree->vdb = std::make_shared<LabelTreeType>(voidLabel);
    openvdb::tree::ValueAccessor<LabelTreeType> acc(*tree->vdb);
    const Vec3i& r = frame.resolution;
    size_t i = 0;
    for (int z = 0; z < r.z; ++z)
        for (int y = 0; y < r.y; ++y)
            for (int x = 0; x < r.x; ++x, ++i)
                if (labels[i] != voidLabel)
                    acc.setValueOn(openvdb::Coord(frame.indexMin.x + x, frame.indexMin.y + y,
                                                  frame.indexMin.z + z),
                                   labels[i]);
    // Uniform blocks become tiles: that is where the memory win comes from.
    tree->vdb->prune();
    return LabelGrid(frame, voidLabel, std::move(tree));
}

LabelGrid LabelGrid::withChanges(const std::vector<Change>& changes) const {
    auto tree = std::make_shared<Tree>();
    tree->vdb = std::make_shared<LabelTreeType>(*tree_->vdb);  // deep copy: this grid stays as it is
    openvdb::tree::ValueAccessor<LabelTreeType> acc(*tree->vdb);
    for (const Change& c : changes) {
        if (!frame_.contains(c.voxel))
            throw std::out_of_range("voxel (" + std::to_string(c.voxel.x) + ", " + std::to_string(c.voxel.y) + ", " +
                                    std::to_string(c.voxel.z) + ") is outside the label grid");
        if (c.label == voidLabel_) acc.setValueOff(toCoord(c.voxel), voidLabel_);
        else acc.setValueOn(toCoord(c.voxel), c.label);
    }
    tree->vdb->prune();
    return LabelGrid(frame_, voidLabel_, std::move(tree));
}

bool LabelGrid::hasSameOccupancyTree(const LabelGrid& other) const {
    return tree_->vdb->hasSameTopology(*other.tree_->vdb);
}

Label LabelGrid::label(const Vec3i& v) const {
    if (!frame_.contains(v)) return voidLabel_;
    return tree_->vdb->getValue(toCoord(v));
}

struct LabelReader::Impl {
    const LabelGrid& grid;
    openvdb::tree::ValueAccessor<const LabelTreeType> accessor;
    explicit Impl(const LabelGrid& g) : grid(g), accessor(*g.tree().vdb) {}
};

LabelReader::LabelReader(const LabelGrid& grid) : impl_(std::make_unique<Impl>(grid)) {}
LabelReader::~LabelReader() = default;

Label LabelReader::at(const Vec3i& v) const {
    if (!impl_->grid.frame().contains(v)) return impl_->grid.voidLabel();
    return impl_->accessor.getValue(toCoord(v));
}

std::vector<Label> LabelGrid::toDense() const {
    const Vec3i& r = frame_.resolution;
    std::vector<Label> out(frame_.voxelCount(), voidLabel_);
    Vec3i lo = frame_.indexMin;
    visitRegions([&](const Vec3i& a, const Vec3i& b, Label l) {
        for (int z = a.z; z <= b.z; ++z)
            for (int y = a.y; y <= b.y; ++y)
                for (int x = a.x; x <= b.x; ++x)
                    out[(size_t(z - lo.z) * r.y + (y - lo.y)) * r.x + (x - lo.x)] = l;
    });
    return out;
}

namespace {
// The frame's voxels as an OpenVDB box (inclusive).
openvdb::CoordBBox frameBoxOf(const GridFrame& frame) {
    const Vec3i last = frame.indexMax() - Vec3i{1, 1, 1};
    return {toCoord(frame.indexMin), toCoord(last)};
}
}  // namespace

void LabelGrid::visitRegions(
    const std::function<void(const Vec3i&, const Vec3i&, Label)>& fn) const {
    if (frame_.voxelCount() == 0) return;
    const openvdb::CoordBBox frameBox = frameBoxOf(frame_);
    // Everything not covered by the tree's values is background (void): the
    // callers start from void, so visit only stored tiles and voxels.
    for (auto it = tree_->vdb->cbeginValueAll(); it; ++it) {
        openvdb::CoordBBox box;
        it.getBoundingBox(box);
        box.intersect(frameBox);
        if (box.empty()) continue;
        Vec3i lo(box.min().x(), box.min().y(), box.min().z());
        Vec3i hi(box.max().x(), box.max().y(), box.max().z());
        fn(lo, hi, *it);
    }
}

void LabelGrid::visitBlockLabels(int log2, const Vec3i& origin,
                                 const std::function<void(const Vec3i&, Label)>& fn) const {
    if (frame_.voxelCount() == 0) return;
    const Vec3i lo = frame_.indexMin, hi{frame_.indexMax().x - 1, frame_.indexMax().y - 1, frame_.indexMax().z - 1};
    auto blockOf = [&](const Vec3i& v) {
        return Vec3i{(v.x - origin.x) >> log2, (v.y - origin.y) >> log2, (v.z - origin.z) >> log2};
    };
    const Vec3i first = blockOf(lo), last = blockOf(hi);
    const Vec3i count{last.x - first.x + 1, last.y - first.y + 1, last.z - first.z + 1};
    auto index = [&](const Vec3i& b) {
        return (size_t(b.z - first.z) * count.y + size_t(b.y - first.y)) * count.x + size_t(b.x - first.x);
    };
    // Voxels of the box [from, to] (inclusive) inside block b.
    auto voxelsIn = [&](const Vec3i& b, const Vec3i& from, const Vec3i& to) {
        uint64_t n = 1;
        for (int a = 0; a < 3; ++a) {
            const int start = origin[a] + (b[a] << log2), end = start + (1 << log2) - 1;
            n *= uint64_t(std::min(to[a], end) - std::max(from[a], start) + 1);
        }
        return n;
    };
    std::vector<uint64_t> covered(size_t(count.x) * count.y * count.z, 0);
    // Stored tiles and voxels, block by block of their box.
    visitRegions([&](const Vec3i& rlo, const Vec3i& rhi, Label l) {
        const Vec3i blo = blockOf(rlo), bhi = blockOf(rhi);
        for (int z = blo.z; z <= bhi.z; ++z)
            for (int y = blo.y; y <= bhi.y; ++y)
                for (int x = blo.x; x <= bhi.x; ++x) {
                    covered[index({x, y, z})] += voxelsIn({x, y, z}, rlo, rhi);
                    fn({x, y, z}, l);
                }
    });
    // Voxels no stored value covers hold the void label.
    for (int z = first.z; z <= last.z; ++z)
        for (int y = first.y; y <= last.y; ++y)
            for (int x = first.x; x <= last.x; ++x)
                if (covered[index({x, y, z})] < voxelsIn({x, y, z}, lo, hi)) fn({x, y, z}, voidLabel_);
}

std::array<uint64_t, 256> LabelGrid::histogram() const {
    std::array<uint64_t, 256> h{};
    uint64_t visited = 0;
    visitRegions([&](const Vec3i& lo, const Vec3i& hi, Label l) {
        uint64_t n = uint64_t(hi.x - lo.x + 1) * uint64_t(hi.y - lo.y + 1) * uint64_t(hi.z - lo.z + 1);
        h[l] += n;
        visited += n;
    });
    // Voxels with no stored value hold the background label.
    h[voidLabel_] += frame_.voxelCount() - visited;
    return h;
}

uint64_t LabelGrid::memoryBytes() const { return tree_->vdb->memUsage(); }

}  // namespace pl

namespace pl {

std::vector<SurfaceVoxel> LabelGrid::surfaceVoxels() const {
    // Leaves and tiles in parallel, each thread into a list of its own;
    // the lists are joined and sorted (z, y, x), so the result does not
    // depend on the threads. A voxel on a tile's edge is found from each of
    // its faces: the sort puts its finds together and they are merged.
    using Leaf = LabelTreeType::LeafNodeType;
    const LabelTreeType& tree = *tree_->vdb;
    const Label voidLabel = voidLabel_;
    const GridFrame& frame = frame_;
    std::vector<const Leaf*> leaves;
    tree.getNodes(leaves);
    struct Tile {
        Vec3i lo, hi;
    };
    std::vector<Tile> tiles;
    if (frame.voxelCount() == 0) return {};
    const openvdb::CoordBBox frameBox = frameBoxOf(frame);
    auto tileIt = tree.cbeginValueAll();
    tileIt.setMaxDepth(LabelTreeType::ValueAllCIter::LEAF_DEPTH - 1);  // tiles only
    for (; tileIt; ++tileIt) {
        if (*tileIt == voidLabel) continue;
        openvdb::CoordBBox box;
        tileIt.getBoundingBox(box);
        box.intersect(frameBox);
        if (!box.empty())
            tiles.push_back({{box.min().x(), box.min().y(), box.min().z()}, {box.max().x(), box.max().y(), box.max().z()}});
    }

    using Accessor = openvdb::tree::ValueAccessor<const LabelTreeType>;
    tbb::enumerable_thread_specific<std::vector<SurfaceVoxel>> found;
    auto isVoid = [&](Accessor& acc, const Vec3i& v) { return !frame.contains(v) || acc.getValue(toCoord(v)) == voidLabel; };
    tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves.size()), [&](const tbb::blocked_range<size_t>& range) {
        Accessor acc(tree);
        std::vector<SurfaceVoxel>& out = found.local();
        for (size_t i = range.begin(); i != range.end(); ++i) {
            const Leaf& leaf = *leaves[i];
            const openvdb::Coord origin = leaf.origin();
            for (openvdb::Index n = 0; n < Leaf::SIZE; ++n) {
                if (leaf.getValue(n) == voidLabel) continue;
                const openvdb::Coord c = leaf.offsetToLocalCoord(n);
                const Vec3i v{origin.x() + c.x(), origin.y() + c.y(), origin.z() + c.z()};
                if (!frame.contains(v)) continue;
                uint8_t exposed = 0;
                for (int k = 0; k < 6; ++k) {
                    const Vec3i& o = kFaceDirections[k];
                    const int lx = c.x() + o.x, ly = c.y() + o.y, lz = c.z() + o.z;
                    const Vec3i u{v.x + o.x, v.y + o.y, v.z + o.z};
                    const bool inLeaf = lx >= 0 && ly >= 0 && lz >= 0 && lx < int(Leaf::DIM) && ly < int(Leaf::DIM) &&
                                        lz < int(Leaf::DIM);
                    const bool isVoidThere =
                        inLeaf ? !frame.contains(u) || leaf.getValue(openvdb::Coord(lx, ly, lz)) == voidLabel : isVoid(acc, u);
                    if (isVoidThere) exposed |= uint8_t(1u << k);
                }
                if (exposed) out.push_back({v, exposed});
            }
        }
    });
    // A tile's voxels touch void only across its faces. A face is looked at
    // in 8 x 8 squares aligned with the leaves: where the voxel across a
    // square's first is held by a tile (not a leaf) of a material, every
    // voxel across the square is, and the square is covered.
    tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size()), [&](const tbb::blocked_range<size_t>& range) {
        Accessor acc(tree);
        std::vector<SurfaceVoxel>& out = found.local();
        for (size_t i = range.begin(); i != range.end(); ++i) {
            const Tile& t = tiles[i];
            for (int k = 0; k < 6; ++k) {
                const Vec3i& o = kFaceDirections[k];
                const int axis = o.x != 0 ? 0 : o.y != 0 ? 1 : 2;
                const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
                Vec3i v;
                v[axis] = o[axis] > 0 ? t.hi[axis] : t.lo[axis];
                for (int s2 = t.lo[a2]; s2 <= t.hi[a2]; s2 = (s2 & ~7) + 8)
                    for (int s1 = t.lo[a1]; s1 <= t.hi[a1]; s1 = (s1 & ~7) + 8) {
                        v[a1] = s1;
                        v[a2] = s2;
                        const Vec3i across{v.x + o.x, v.y + o.y, v.z + o.z};
                        if (frame.contains(across)) {
                            const openvdb::Coord c = toCoord(across);
                            const int depth = acc.getValueDepth(c);  // -1: background; DEPTH - 1: a leaf's voxel
                            if (depth >= 0 && depth < int(LabelTreeType::DEPTH) - 1 && acc.getValue(c) != voidLabel)
                                continue;  // covered
                        }
                        const int e1 = std::min(t.hi[a1], (s1 & ~7) + 7), e2 = std::min(t.hi[a2], (s2 & ~7) + 7);
                        for (int u2 = s2; u2 <= e2; ++u2)
                            for (int u1 = s1; u1 <= e1; ++u1) {
                                v[a1] = u1;
                                v[a2] = u2;
                                if (isVoid(acc, {v.x + o.x, v.y + o.y, v.z + o.z})) out.push_back({v, uint8_t(1u << k)});
                            }
                    }
            }
        }
    });
    std::vector<SurfaceVoxel> all;
    for (const std::vector<SurfaceVoxel>& list : found) all.insert(all.end(), list.begin(), list.end());
    found.clear();
    tbb::parallel_sort(all.begin(), all.end(), [](const SurfaceVoxel& a, const SurfaceVoxel& b) {
        return a.voxel.z != b.voxel.z ? a.voxel.z < b.voxel.z
                                      : (a.voxel.y != b.voxel.y ? a.voxel.y < b.voxel.y : a.voxel.x < b.voxel.x);
    });
    size_t n = 0;
    for (size_t i = 0; i < all.size(); ++i) {
        if (n > 0 && all[n - 1].voxel == all[i].voxel) all[n - 1].exposedFaces |= all[i].exposedFaces;
        else all[n++] = all[i];
    }
    all.resize(n);
    all.shrink_to_fit();
    return all;
}

struct LabelGridBuilder::Impl {
    GridFrame frame;
    Label voidLabel;
    std::shared_ptr<LabelGrid::Tree> tree;
    openvdb::tree::ValueAccessor<LabelTreeType> accessor;
    Impl(const GridFrame& f, Label v, std::shared_ptr<LabelGrid::Tree> t)
        : frame(f), voidLabel(v), tree(std::move(t)), accessor(*tree->vdb) {}
};

LabelGridBuilder::LabelGridBuilder(const GridFrame& frame, Label voidLabel) {
    initializeVdb();
    auto tree = std::make_shared<LabelGrid::Tree>();
    tree->vdb = std::make_shared<LabelTreeType>(voidLabel);
    impl_ = std::make_unique<Impl>(frame, voidLabel, std::move(tree));
}

LabelGridBuilder::~LabelGridBuilder() = default;

void LabelGridBuilder::set(const Vec3i& v, Label label) {
    if (label != impl_->voidLabel) impl_->accessor.setValueOn(toCoord(v), label);
}

void LabelGridBuilder::compact() {
    impl_->accessor.clear();
    impl_->tree->vdb->prune();
}

LabelGrid LabelGridBuilder::finish() {
    compact();
    return LabelGrid(impl_->frame, impl_->voidLabel, impl_->tree);
}

}  // namespace pl
