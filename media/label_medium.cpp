#include "media/label_medium.h"

#include "media/label_tree.h"

namespace pl {

LabelMedium::LabelMedium(LabelGrid grid, MaterialTable materials)
    : grid_(std::move(grid)), materials_(std::move(materials)) {
    for (int c = 0; c < 3; ++c) luts_[c] = ChannelLut::build(materials_, grid_.voidLabel(), c);
    majorants_ = MajorantGrid(grid_, luts_);
    scale_ = grid_.frame().worldToCellScale();
    offset_ = grid_.frame().worldToCellOffset();
}

struct LabelMedium::Sampler::Impl {
    openvdb::tree::ValueAccessor<const LabelTreeType> accessor;
    explicit Impl(const LabelTreeType& tree) : accessor(tree) {}
};

LabelMedium::Sampler::Sampler(const LabelMedium& medium)
    : impl_(std::make_unique<Impl>(*medium.grid_.tree().vdb)), medium_(medium) {}
LabelMedium::Sampler::~Sampler() = default;

Label LabelMedium::Sampler::labelAt(const Vec3i& v) {
    if (!medium_.frame().contains(v)) return medium_.grid_.voidLabel();
    return impl_->accessor.getValue(toCoord(v));
}

FreeFlight LabelMedium::Sampler::sampleFreeFlight(const Ray& ray, float tMax_mm, int channel,
                                                  Rng& rng) {
    auto& acc = impl_->accessor;
    return deltaTrack(medium_.toCellRay(ray), tMax_mm, medium_.frame(), medium_.majorants_,
                      medium_.luts_[channel], channel,
                      [&acc](const Vec3i& v) { return acc.getValue(toCoord(v)); }, rng);
}

float LabelMedium::Sampler::transmittance(const Ray& ray, float tMax_mm, int channel) {
    auto& acc = impl_->accessor;
    return regularTrack(medium_.toCellRay(ray), tMax_mm, medium_.frame(), medium_.majorants_,
                        medium_.luts_[channel], channel,
                        [&acc](const Vec3i& v) { return acc.getValue(toCoord(v)); });
}

}  // namespace pl
