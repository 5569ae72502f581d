#include "render/progressive_render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <stdexcept>

#include "io/image_io.h"
#include "runtime/distributed.h"

namespace pl {

double medianRelativeError(const Film& film, const Sensor& sensor, const RadianceImage* ref, bool skipExact) {
    double worst = 0;
    for (int c = 0; c < 3; ++c) {
        std::vector<double> rel;
        rel.reserve(film.pixelCount());
        for (size_t p = 0; p < film.pixelCount(); ++p) {
            const double m = film.mean(p, c);
            if (!ref) {
                const double se = film.standardError(p, c);
                if (skipExact && !(se > 0)) continue;
                rel.push_back(m > 0 ? se / m : INFINITY);
                continue;
            }
            const int64_t i = sensor.pixelImageIndex(p);
            if (i < 0) continue;
            const double r = ref->mean[size_t(i)][c];
            rel.push_back(r > 0 ? std::abs(m - r) / r / 0.6745 : INFINITY);
        }
        if (rel.empty()) continue;
        std::nth_element(rel.begin(), rel.begin() + long(rel.size() / 2), rel.end());
        worst = std::max(worst, rel[rel.size() / 2]);
    }
    return worst;
}

ProgressiveRender renderProgressively(const Scene& scene, const Sensor& sensor, const RenderSettings& settings,
                                      const std::function<void(const RenderResult&, uint32_t)>& onRound,
                                      bool acrossRanks) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
    ProgressiveRender out{RenderResult{Film(sensor.pixelCount())}, 0, 0, "spp"};
    const PixelShare share = acrossRanks ? PixelShare::ofThisRank(sensor.pixelCount()) : PixelShare{};
    const bool decides = !share.acrossRanks || Distributed::rank() == 0;
    std::unique_ptr<Integrator> integrator;
    runOnEveryRank([&] { integrator = makeIntegrator(scene, sensor, settings); }, share.acrossRanks);
    const bool timed = settings.timeBudget_s > 0, targeted = settings.targetRelativeError > 0;
    // After a round (on the rank that decides): the next round's samples,
    // 0 to stop. Double (an image after each round), or fewer where the
    // target asks for fewer (error falls as 1 / sqrt(samples)), within the
    // time left.
    auto nextRound = [&]() -> uint32_t {
        if (out.spp >= settings.spp) return 0;
        if (targeted && out.medianRelativeError <= settings.targetRelativeError) {
            out.stoppedBy = "target error";
            return 0;
        }
        const double perSample = out.result.seconds / out.spp;
        if (timed && out.result.seconds + perSample >= settings.timeBudget_s) {
            out.stoppedBy = "time";
            return 0;
        }
        double next = out.spp;
        if (targeted && std::isfinite(out.medianRelativeError))
            next = std::min(next, std::max(1.0, std::ceil(out.spp * (std::pow(out.medianRelativeError / settings.targetRelativeError, 2) - 1.0))));
        if (timed) next = std::min(next, std::floor((settings.timeBudget_s - out.result.seconds) / perSample));
        return uint32_t(std::clamp(next, 1.0, double(settings.spp - out.spp)));
    };
    // Across ranks a failure of rank 0's (writing the images) must stop
    // the others, which wait for its decision.
    constexpr uint32_t kRankZeroFailed = ~0u;
    PathStats allStats;  // over the ranks, on the rank that decides (out.result's are this rank's)
    for (uint32_t round = 1; round > 0;) {
        runOnEveryRank([&] { renderSamples(*integrator, scene, sensor, settings, share, out.spp, round, out.result); },
                       share.acrossRanks);
        out.spp += round;
        allStats = gatherShares(out.result, share, sensor);
        out.result.seconds = elapsed();
        uint32_t next = 0;
        std::exception_ptr failure;
        if (decides) try {
                out.medianRelativeError = medianRelativeError(out.result.film, sensor, nullptr, true);
                if (onRound) onRound(out.result, out.spp);
                next = nextRound();
            } catch (...) {
                if (!share.acrossRanks) throw;
                failure = std::current_exception();
                next = kRankZeroFailed;
            }
        round = share.acrossRanks ? broadcastFromRankZero(next) : next;
        if (failure) std::rethrow_exception(failure);
        if (round == kRankZeroFailed) throw std::runtime_error("MPI rank 0 failed");
    }
    out.result.stats = allStats;
    return out;
}

}  // namespace pl
