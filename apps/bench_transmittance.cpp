#include "apps/bench_transmittance.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iterator>
#include <stdexcept>
#include <vector>

#include "core/mesh_point_sampler.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "media/label_medium.h"

namespace pl {

namespace {
constexpr size_t kSegments = 2000;  // per length and channel
constexpr int kRepeats = 16;        // estimates of each segment by each stochastic estimator
constexpr float kLengths_voxels[] = {2, 8, 32};
// Entries tried per segment kept before the mesh is taken as open.
constexpr size_t kMostTriesPerSegment = 100;

struct Segment {
    Ray ray;
    float length_mm;
    double exact;
};

struct Measured {
    double seconds = 0;
    double estimates = 0;
    double varianceSum = 0;  // of each segment's own variance
    double differenceSum = 0, differenceSumSq = 0;
};

// Estimates every segment kRepeats times with estimate(segment, rng).
Measured measure(const std::vector<Segment>& segments, uint64_t seed,
                 const std::function<float(const Segment&, Rng&)>& estimate) {
    Measured m;
    std::vector<float> values(segments.size() * kRepeats);
    const auto start = std::chrono::steady_clock::now();
    for (size_t i = 0; i < segments.size(); ++i) {
        Rng rng = Rng::forPath(seed, i, 0, 0);
        for (int k = 0; k < kRepeats; ++k) values[i * kRepeats + size_t(k)] = estimate(segments[i], rng);
    }
    m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    m.estimates = double(values.size());
    for (size_t i = 0; i < segments.size(); ++i) {
        double sum = 0, sumSq = 0;
        for (int k = 0; k < kRepeats; ++k) {
            const double v = values[i * kRepeats + size_t(k)];
            sum += v;
            sumSq += v * v;
        }
        const double mean = sum / kRepeats;
        m.varianceSum += std::max(0.0, (sumSq - kRepeats * mean * mean) / (kRepeats - 1));
        const double difference = mean - segments[i].exact;
        m.differenceSum += difference;
        m.differenceSumSq += difference * difference;
    }
    return m;
}
}  // namespace

std::string transmittanceTable(const Scene& scene, uint64_t seed) {
    const LabelMedium& medium = *scene.medium;
    const Geometry& geometry = *scene.geometry;
    const Vec3f voxel = medium.frame().voxelSize_mm;
    const float voxel_mm = std::min(voxel.x, std::min(voxel.y, voxel.z));
    LabelMedium::Tracker tracker(medium);
    MeshPointSampler entries(geometry);
    std::string md =
        "Transmittance along fixed segments inside the object (bench --transmittance; one thread): "
        "regular tracking exact, ratio tracking and pins unbiased estimates of it "
        "(media/segment_transmittance.h). " +
        std::to_string(kSegments) + " segments per length and channel, each estimated " +
        std::to_string(kRepeats) +
        " times; variance: the mean over segments of each one's own; difference: the mean of (estimate - exact) "
        "over the segments, with its standard error.\n\n"
        "| channel | length (voxels) | mean T | estimator | ns per estimate | variance | variance x time (ns) | "
        "difference |\n|---|---|---|---|---|---|---|---|\n";
    for (int channel = 0; channel < 3; ++channel)
        for (size_t lengthIndex = 0; lengthIndex < std::size(kLengths_voxels); ++lengthIndex) {
            const float length_voxels = kLengths_voxels[lengthIndex];
            std::vector<Segment> segments;
            Rng rng(seed, uint64_t(channel) * std::size(kLengths_voxels) + lengthIndex);
            for (size_t tries = 0; segments.size() < kSegments; ++tries) {
                if (tries > kMostTriesPerSegment * kSegments)
                    throw std::runtime_error("bench --transmittance: rays into the mesh do not leave it (an open mesh?)");
                const SurfaceHit entry = entries.sample(rng);
                const float u0 = rng.uniform(), u1 = rng.uniform();
                const Vec3f d = -Frame(entry.ng).toWorld(sampleCosineHemisphere(u0, u1).d);
                const Ray ray = geometry.spawnRay(entry.p, entry.ng, d);
                const std::optional<SurfaceHit> exit = geometry.intersectFromInside(ray);
                if (!exit) continue;
                const float length_mm = std::min(exit->t, length_voxels * voxel_mm);
                segments.push_back({ray, length_mm, double(tracker.transmittance(ray, length_mm, channel))});
            }
            double meanT = 0;
            for (const Segment& s : segments) meanT += s.exact / double(segments.size());
            const Measured regular = measure(segments, seed, [&](const Segment& s, Rng&) {
                return tracker.transmittance(s.ray, s.length_mm, channel);
            });
            const Measured ratio = measure(segments, seed, [&](const Segment& s, Rng& r) {
                return tracker.ratioTrackedTransmittance(s.ray, s.length_mm, channel, r);
            });
            const Measured pins = measure(segments, seed, [&](const Segment& s, Rng& r) {
                return tracker.pinTransmittance(s.ray, s.length_mm, channel, r);
            });
            for (const auto& [name, m] : {std::pair<const char*, const Measured&>{"regular (exact)", regular},
                                          {"ratio tracking", ratio},
                                          {"pins", pins}}) {
                const double n = double(segments.size());
                const double ns = m.seconds / m.estimates * 1e9;
                const double variance = m.varianceSum / n;
                const double difference = m.differenceSum / n;
                const double differenceError =
                    std::sqrt(std::max(0.0, m.differenceSumSq / n - difference * difference) / (n - 1));
                char line[256];
                std::snprintf(line, sizeof line, "| %c | %.0f | %.4f | %s | %.0f | %.3g | %.3g | %+.1e +- %.1e |\n",
                              "RGB"[channel], length_voxels, meanT, name, ns, variance, variance * ns, difference,
                              differenceError);
                md += line;
            }
        }
    return md;
}

}  // namespace pl
