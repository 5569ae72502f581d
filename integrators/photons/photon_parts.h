// The photons of one iteration of a progressive photon estimator (bre's,
// pp3d's and combined's points, pb2d's and bb1d's beams): they enter from the environment,
// uniform by area over the mesh with cosine-weighted directions, each
// carrying the power the environment sends in (Le pi A) over their count,
// and walk with volpath's walk (walkParticleIn). They are traced in
// kPhotonParts parts, each by one thread, and put together in part order:
// the same bits whatever the threads. What a photon leaves grows with its
// walk (a point per collision, a beam per flight: about 50 in white
// resin), so a part stops the iteration with an error once the items
// stored outgrow the memory there was when the source was made.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/mesh_point_sampler.h"
#include "core/path_stats.h"
#include "core/rng.h"
#include "integrators/volume_walk.h"
#include "media/label_medium.h"
#include "runtime/interrupt.h"
#include "runtime/memory_budget.h"
#include "runtime/scheduler.h"
#include "scene/scene.h"

namespace pl {

constexpr size_t kPhotonParts = 64;

class PhotonSource {
public:
    // photonsPerPixel x pixelCount photons an iteration (one at least),
    // their random streams keyed by the seed and the estimator's salt; each
    // stored item (`items`, e.g. "photons") takes bytesEach while its
    // iteration's map is built. Refuses (an error starting with
    // `estimator`) when one item a photon does not fit; remedy: the option
    // that lowers the count.
    PhotonSource(const Scene& scene, Majorants majorants, float photonsPerPixel, size_t pixelCount, uint64_t seed,
                 uint64_t salt, uint64_t bytesEach, const std::string& estimator, const std::string& items,
                 std::string remedy)
        : scene_(scene),
          majorants_(majorants),
          count_(std::max<uint64_t>(1, uint64_t(std::llround(double(photonsPerPixel) * double(pixelCount))))),
          seed_(mix64(seed ^ salt)),
          entries_(*scene.geometry),
          remedy_(std::move(remedy)) {
        if (auto why = memoryShortfall(count_ * bytesEach, std::to_string(count_) + " " + items + " an iteration",
                                       memoryInUseBytes()))
            throw std::runtime_error(estimator + ": " + *why);
        mostStored_ = itemsTheMemoryHolds(bytesEach);
    }

    uint64_t count() const { return count_; }
    // The surface the photons enter through, uniformly by area.
    double area_mm2() const { return entries_.area_mm2(); }

    // The photons of sample `sample` in a channel. Each photon's walk calls
    // onFlight(stored, ray, tEnd_mm, path) for every flight and
    // onCollision(stored, y, dIn, label, path) at every real collision
    // (walkVolume's hooks), where `stored` is its part's items and
    // path.beta x powerEach the power it carries.
    template <class Stored, class OnFlight, class OnCollision>
    std::vector<Stored> trace(int channel, uint32_t sample, PathStats& stats, OnFlight&& onFlight,
                              OnCollision&& onCollision) const {
        const ChannelLut& lut = scene_.medium->lut(channel);
        const float Le = scene_.environment[channel];
        if (!(Le > 0.0f)) return {};
        std::vector<std::vector<Stored>> parts(kPhotonParts);
        std::vector<PathStats> partStats(kPhotonParts);
        const uint64_t mostPerPart = mostStored_ / kPhotonParts;
        parallelForTiles(kPhotonParts, 1, [&](size_t begin, size_t end) {
            LabelMedium::Tracker medium(*scene_.medium, majorants_);
            for (size_t part = begin; part < end; ++part) {
                std::vector<Stored>& stored = parts[part];
                const uint64_t first = count_ * part / kPhotonParts;
                for (uint64_t i = first; i < count_ * (part + 1) / kPhotonParts; ++i) {
                    if (interruptRequested()) return;
                    Rng rng = Rng::forPath(seed_, i, sample, uint64_t(channel));
                    const SurfaceHit entry = entries_.sample(rng);
                    SingleChannelPath path{&lut, channel, Le};
                    walkParticleIn(
                        scene_, VolPathOptions{}, entry, path, medium, rng, partStats[part],
                        [&](const Ray& flight, float tEnd_mm, const SingleChannelPath& p) {
                            onFlight(stored, flight, tEnd_mm, p);
                        },
                        [&](const Point3f& y, const Vec3f& dIn, Label label, const SingleChannelPath& p) {
                            onCollision(stored, y, dIn, label, p);
                        });
                    if (stored.size() > mostPerPart)
                        throw std::runtime_error("one iteration's photons outgrow the memory (" +
                                                 std::to_string(stored.size()) + " items stored by " +
                                                 std::to_string(i + 1 - first) + " of " + std::to_string(count_) +
                                                 " photons; room for " + std::to_string(mostStored_) + "): " +
                                                 remedy_);
                }
            }
        });
        std::vector<Stored> all;
        size_t total = 0;
        for (const auto& part : parts) total += part.size();
        all.reserve(total);
        for (size_t part = 0; part < kPhotonParts; ++part) {
            all.insert(all.end(), parts[part].begin(), parts[part].end());
            std::vector<Stored>().swap(parts[part]);
            stats += partStats[part];
        }
        return all;
    }

    // The power each photon of a channel enters with (Le pi A over the
    // count; cosine-weighted directions cancel the pi).
    double powerEach(int channel) const {
        return double(scene_.environment[channel]) * kPi * entries_.area_mm2() / double(count_);
    }

private:
    const Scene& scene_;
    Majorants majorants_;
    uint64_t count_;
    uint64_t seed_;
    MeshPointSampler entries_;  // where photons enter
    std::string remedy_;
    uint64_t mostStored_;       // the items the memory left when the source was made holds
};

}  // namespace pl
