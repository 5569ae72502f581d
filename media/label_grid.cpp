#include "media/label_grid.h"

#include <algorithm>
#include <mutex>
#include <stdexcept>
#include <string>

#include "media/label_tree.h"

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

void LabelGrid::visitRegions(
    const std::function<void(const Vec3i&, const Vec3i&, Label)>& fn) const {
    Vec3i fmin = frame_.indexMin, fmax = frame_.indexMax();
    openvdb::CoordBBox frameBox(toCoord(fmin), openvdb::Coord(fmax.x - 1, fmax.y - 1, fmax.z - 1));
    if (frame_.voxelCount() == 0) return;
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
    std::vector<SurfaceVoxel> out;
    openvdb::tree::ValueAccessor<const LabelTreeType> acc(*tree_->vdb);
    auto isVoid = [&](const Vec3i& v) {
        return !frame_.contains(v) || acc.getValue(toCoord(v)) == voidLabel_;
    };
    auto check = [&](const Vec3i& v) {
        uint8_t exposed = 0;
        for (int k = 0; k < 6; ++k) {
            const Vec3i& o = kFaceDirections[k];
            if (isVoid({v.x + o.x, v.y + o.y, v.z + o.z})) exposed |= uint8_t(1u << k);
        }
        if (exposed) out.push_back({v, exposed});
    };
    visitRegions([&](const Vec3i& lo, const Vec3i& hi, Label l) {
        if (l == voidLabel_) return;
        // Inside a uniform tile only voxels on the tile's faces can touch void.
        for (int z = lo.z; z <= hi.z; ++z)
            for (int y = lo.y; y <= hi.y; ++y) {
                bool interiorRow = z > lo.z && z < hi.z && y > lo.y && y < hi.y;
                for (int x = lo.x; x <= hi.x; x = (interiorRow && x == lo.x && hi.x > lo.x) ? hi.x : x + 1)
                    check({x, y, z});
            }
    });
    std::sort(out.begin(), out.end(), [](const SurfaceVoxel& a, const SurfaceVoxel& b) {
        return a.voxel.z != b.voxel.z ? a.voxel.z < b.voxel.z
                                      : (a.voxel.y != b.voxel.y ? a.voxel.y < b.voxel.y : a.voxel.x < b.voxel.x);
    });
    return out;
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
