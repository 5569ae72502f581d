#include "media/label_medium.h"

#include <algorithm>
#include <stdexcept>

#include "media/collision_events.h"
#include "media/segment_transmittance.h"

#include "media/label_tree.h"
#include "media/voxel_fields_vdb.h"

namespace pl {

LabelMedium::LabelMedium(LabelGrid grid, MaterialTable materials)
    : grid_(std::move(grid)), materials_(std::move(materials)) {
    for (int c = 0; c < 3; ++c) luts_[c] = ChannelLut::build(materials_, grid_.voidLabel(), c);
    majorants_ = MajorantGrid(grid_, luts_);
    uniform_ = UniformRegions(grid_);
    scale_ = grid_.frame().worldToCellScale();
    offset_ = grid_.frame().worldToCellOffset();
}

LabelMedium::LabelMedium(LabelGrid grid, const LabelMedium& previous, const std::vector<Vec3i>& changed,
                         bool majorantsOnlyRise)
    : grid_(std::move(grid)), materials_(previous.materials_), luts_(previous.luts_), majorants_(previous.majorants_),
      uniform_(previous.uniform_), fields_(previous.fields_) {
    majorants_.update(grid_, luts_, changed, majorantsOnlyRise);
    uniform_.update(grid_, changed);
    scale_ = grid_.frame().worldToCellScale();
    offset_ = grid_.frame().worldToCellOffset();
}

struct LabelMedium::Tracker::Impl {
    openvdb::tree::ValueAccessor<const LabelTreeType> accessor;
    std::unique_ptr<openvdb::FloatGrid::ConstAccessor> sdf;
    std::unique_ptr<openvdb::Vec3SGrid::ConstAccessor> normal;
    Impl(const LabelTreeType& tree, const VoxelFields* fields) : accessor(tree) {
        if (!fields) return;
        sdf = std::make_unique<openvdb::FloatGrid::ConstAccessor>(fields->grids().sdf->getConstAccessor());
        normal = std::make_unique<openvdb::Vec3SGrid::ConstAccessor>(fields->grids().normal->getConstAccessor());
    }
};

namespace {
// The label lookup the trackers take as a template parameter (inlined in
// their loops): through this thread's OpenVDB accessor.
template <class Accessor>
auto labelLookup(Accessor& acc) {
    return [&acc](const Vec3i& v) PL_ALWAYS_INLINE { return acc.getValue(toCoord(v)); };
}
// The ray's per-brick majorant segments (forEachBrickSegment bound to it).
auto brickSegments(const CellRay& ray, float tMax_mm, const GridFrame& frame, const MajorantGrid& majorants) {
    return [&ray, tMax_mm, &frame, &majorants](auto&& visit) PL_ALWAYS_INLINE {
        return forEachBrickSegment(ray, tMax_mm, frame, majorants, visit);
    };
}
}  // namespace

LabelMedium::Tracker::Tracker(const LabelMedium& medium, Majorants majorants)
    : impl_(std::make_unique<Impl>(*medium.grid_.tree().vdb, medium.fields_.get())), medium_(medium),
      majorants_(majorants) {}

std::optional<LabelMedium::Tracker::NearestSurface> LabelMedium::Tracker::nearestSurface(const Point3f& p) {
    if (!impl_->normal) return std::nullopt;
    openvdb::Coord c = toCoord(medium_.voxelAt(p));
    openvdb::Vec3s n;
    if (!impl_->normal->probeValue(c, n)) return std::nullopt;  // outside the band
    return NearestSurface{{n.x(), n.y(), n.z()}, impl_->sdf->getValue(c)};
}
LabelMedium::Tracker::~Tracker() = default;

Label LabelMedium::Tracker::labelAt(const Vec3i& v) {
    if (!medium_.frame().contains(v)) return medium_.grid_.voidLabel();
    if (reads_) reads_->labels.push_back({medium_.majorants_.voxelKey(v)});
    return impl_->accessor.getValue(toCoord(v));
}

namespace {
// Events that say, of each label read at a tentative collision, how much
// of it the decision used (LabelRead): a null collision of delta tracking
// only that the extinction stayed at or below u * majorant. The same
// random numbers and decisions as the events alone.
template <class Events>
struct RecordedEvents {
    Events& events;
    LabelReads& reads;
    PL_ALWAYS_INLINE float enter(const MajorantSegment& s) { return events.enter(s); }
    PL_ALWAYS_INLINE bool collides(float t, Label l, Rng& rng) { return events.collides(t, l, rng); }
    PL_ALWAYS_INLINE void leave(float t) { events.leave(t); }
};

template <>
struct RecordedEvents<DeltaEvents> {
    DeltaEvents& events;
    LabelReads& reads;
    PL_ALWAYS_INLINE float enter(const MajorantSegment& s) { return events.enter(s); }
    PL_ALWAYS_INLINE bool collides(float /*t*/, Label l, Rng& rng) {
        if (events.everyCollisionReal) return true;  // decided without the label: any relabelling meets the read
        const float threshold = rng.uniform() * events.sigmaMaj;
        if (threshold < events.lut.sigmaT_perMm[l]) return true;
        reads.labels.back().sameUpTo_perMm = threshold;
        reads.labels.back().channel = events.channel;
        return false;
    }
    PL_ALWAYS_INLINE void leave(float t) { events.leave(t); }
};
}  // namespace

template <class Events>
FreeFlight LabelMedium::Tracker::sampleFlight(const Ray& ray, float tMax_mm, Events& events, Rng& rng) {
    auto& acc = impl_->accessor;
    auto labelAt = labelLookup(acc);
    const CellRay cellRay = medium_.toCellRay(ray);
    if (majorants_ == Majorants::Global) {
        auto segments = [&](auto&& visit) {
            return wholeGridSegment(cellRay, tMax_mm, medium_.frame(), medium_.majorants_.wholeGrid(), visit);
        };
        return sampleMajorantFlight(cellRay, segments, events, labelAt, rng);
    }
    const MajorantGrid& majorants = medium_.majorants_;
    if (reads_) {
        auto recorded = [&](auto&& visit) {
            return forEachBrickSegment(cellRay, tMax_mm, medium_.frame(), majorants,
                                       [&](const MajorantSegment& segment, FreeFlight& out) PL_ALWAYS_INLINE {
                                           reads_->bricks.push_back(uint32_t(majorants.brickIndexOf(*segment.bounds)));
                                           return visit(segment, out);
                                       });
        };
        auto recordedLabelAt = [&](const Vec3i& v) PL_ALWAYS_INLINE {
            reads_->labels.push_back({majorants.voxelKey(v)});
            return acc.getValue(toCoord(v));
        };
        RecordedEvents<Events> recordedEvents{events, *reads_};
        return sampleMajorantFlight(cellRay, recorded, recordedEvents, recordedLabelAt, rng);
    }
    return sampleMajorantFlight(cellRay, brickSegments(cellRay, tMax_mm, medium_.frame(), majorants), events, labelAt,
                                rng);
}

FreeFlight LabelMedium::Tracker::sampleFreeFlight(const Ray& ray, float tMax_mm, int channel, Rng& rng) {
    if (majorants_ == Majorants::Decomposition) {
        const CellRay cellRay = medium_.toCellRay(ray);
        return sampleDecomposedFlight(cellRay, brickSegments(cellRay, tMax_mm, medium_.frame(), medium_.majorants_),
                                      medium_.luts_[channel], channel, labelLookup(impl_->accessor), rng);
    }
    DeltaEvents events{medium_.luts_[channel], channel};
    return sampleFlight(ray, tMax_mm, events, rng);
}

FreeFlight LabelMedium::Tracker::sampleFreeFlightHero(const Ray& ray, float tMax_mm, int hero, Rng& rng,
                                                      RGB& logRatio) {
    if (majorants_ == Majorants::Decomposition) throw std::logic_error("decomposition tracking follows one channel");
    HeroEvents events{medium_.luts_, hero, logRatio};
    return sampleFlight(ray, tMax_mm, events, rng);
}

FreeFlight LabelMedium::Tracker::sampleFreeFlightSpectral(const Ray& ray, float tMax_mm, Rng& rng, RGB& weight) {
    if (majorants_ == Majorants::Decomposition) throw std::logic_error("decomposition tracking follows one channel");
    SpectralEvents events{medium_.luts_, weight};
    return sampleFlight(ray, tMax_mm, events, rng);
}

FreeFlight LabelMedium::Tracker::freeFlightAtDepth(const Ray& ray, float tMax_mm, int channel,
                                                   float opticalDepth) {
    auto& acc = impl_->accessor;
    return inverseTrack(medium_.toCellRay(ray), tMax_mm, opticalDepth, medium_.frame(), medium_.majorants_,
                        medium_.luts_[channel], channel, labelLookup(acc));
}

float LabelMedium::Tracker::ratioTrackedTransmittance(const Ray& ray, float tMax_mm, int channel, Rng& rng) {
    auto& acc = impl_->accessor;
    return ratioTrack(medium_.toCellRay(ray), tMax_mm, medium_.frame(), medium_.majorants_, medium_.luts_[channel],
                      channel, labelLookup(acc), rng);
}

float LabelMedium::Tracker::pinTransmittance(const Ray& ray, float tMax_mm, int channel, Rng& rng) {
    auto& acc = impl_->accessor;
    return pinTrack(medium_.toCellRay(ray), tMax_mm, medium_.frame(), medium_.majorants_, medium_.luts_[channel],
                    channel, labelLookup(acc), rng);
}

float LabelMedium::Tracker::transmittance(const Ray& ray, float tMax_mm, int channel,
                                          TransmittanceRoulette roulette) {
    auto& acc = impl_->accessor;
    return regularTrack(medium_.toCellRay(ray), tMax_mm, medium_.frame(), medium_.majorants_,
                        medium_.luts_[channel], channel,
                        labelLookup(acc), roulette);
}

GridCoefficients gridCoefficientsOf(const LabelMedium& medium) {
    const std::array<uint64_t, 256> voxels = medium.grid().histogram();
    GridCoefficients g;
    for (int l = 0; l < 256; ++l) {
        if (voxels[size_t(l)] == 0 || l == medium.grid().voidLabel()) continue;
        for (int c = 0; c < 3; ++c) {
            const ChannelLut& lut = medium.lut(c);
            g.leastSigmaT[c] = std::min(g.leastSigmaT[c], lut.sigmaT_perMm[size_t(l)]);
            g.mostSigmaS[c] = std::max(g.mostSigmaS[c], lut.sigmaT_perMm[size_t(l)] * lut.albedo[size_t(l)]);
        }
    }
    return g;
}

}  // namespace pl
