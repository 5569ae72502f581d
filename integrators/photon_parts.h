// The photons of one iteration of a progressive photon estimator (bre's
// points, pb2d's and bb1d's beams), traced in kPhotonParts parts, each by
// one thread, and put together in part order: the same bits whatever the
// threads. What a photon leaves grows with its walk (a point per
// collision, a beam per flight: about 50 in white resin), so a part stops
// the iteration with an error once the items stored outgrow the memory
// there was when the estimator was made.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/path_stats.h"
#include "media/label_medium.h"
#include "runtime/interrupt.h"
#include "runtime/scheduler.h"
#include "scene/scene.h"

namespace pl {

constexpr size_t kPhotonParts = 64;

// Photon i (of `count`) is traced by tracePhoton(i, stored, medium, stats),
// which appends what it leaves to `stored`. mostStored: the items the
// memory holds; remedy: the option that lowers it.
template <class Stored, class TracePhoton>
std::vector<Stored> tracePhotonsInParts(const Scene& scene, Majorants majorants, uint64_t count, uint64_t mostStored,
                                        const std::string& remedy, PathStats& stats, TracePhoton&& tracePhoton) {
    std::vector<std::vector<Stored>> parts(kPhotonParts);
    std::vector<PathStats> partStats(kPhotonParts);
    const uint64_t mostPerPart = mostStored / kPhotonParts;
    parallelForTiles(kPhotonParts, 1, [&](size_t begin, size_t end) {
        LabelMedium::Tracker medium(*scene.medium, majorants);
        for (size_t part = begin; part < end; ++part) {
            const uint64_t first = count * part / kPhotonParts;
            for (uint64_t i = first; i < count * (part + 1) / kPhotonParts; ++i) {
                if (interruptRequested()) return;
                tracePhoton(i, parts[part], medium, partStats[part]);
                if (parts[part].size() > mostPerPart)
                    throw std::runtime_error("one iteration's photons outgrow the memory (" +
                                             std::to_string(parts[part].size()) + " items stored by " +
                                             std::to_string(i + 1 - first) + " of " + std::to_string(count) +
                                             " photons; room for " + std::to_string(mostStored) + "): " + remedy);
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

}  // namespace pl
