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
            const double m = film.mean(p, c), se = film.standardError(p, c);
            if (skipExact && !(se > 0)) continue;
            if (!ref) {
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

RenderRounds::RenderRounds(const Scene& scene, const Sensor& sensor, const RenderSettings& settings, bool acrossRanks,
                           bool filmOnEveryRank)
    : scene_(scene),
      sensor_(sensor),
      settings_(settings),
      share_(acrossRanks ? PixelShare::ofThisRank(sensor.pixelCount()) : PixelShare{}),
      filmOnEveryRank_(filmOnEveryRank),
      result_{Film(sensor.pixelCount())} {
    runOnEveryRank([&] { integrator_ = makeIntegrator(scene, sensor, settings); },
                   share_.acrossRanks);
}

RenderRounds::~RenderRounds() = default;

void RenderRounds::render(const std::vector<uint32_t>* pixels, uint32_t first, uint32_t count) {
    PixelShare share = share_;
    if (pixels && !share_.acrossRanks) share.pixels = *pixels;
    if (pixels && share_.acrossRanks) {
        share.pixels.clear();
        for (uint32_t p : *pixels)
            if (rankOfPixel(p, Distributed::ranks()) == Distributed::rank()) share.pixels.push_back(p);
    }
    runOnEveryRank(
        [&] { renderSamples(*integrator_, scene_, sensor_, settings_, share, first, count, result_, false, footprints_,
                                 coupled_); },
        share_.acrossRanks);
    stats_ = gatherShares(result_, share, sensor_);
    if (share_.acrossRanks && filmOnEveryRank_) broadcastFromRankZero(result_.film, stats_);
}

ProgressiveRender renderProgressively(const Scene& scene, const Sensor& sensor, const RenderSettings& settings,
                                      const std::function<void(const RenderResult&, uint32_t)>& onRound,
                                      bool acrossRanks) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
    RenderRounds rounds(scene, sensor, settings, acrossRanks);
    ProgressiveRender out;
    out.stoppedBy = "spp";
    const bool decides = !rounds.acrossRanks() || Distributed::rank() == 0;
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
        const double seconds = rounds.result().seconds;
        const double perSample = seconds / out.spp;
        if (timed && seconds + perSample >= settings.timeBudget_s) {
            out.stoppedBy = "time";
            return 0;
        }
        double next = out.spp;
        if (targeted && std::isfinite(out.medianRelativeError))
            next = std::min(next, std::max(1.0, std::ceil(out.spp * (std::pow(out.medianRelativeError / settings.targetRelativeError, 2) - 1.0))));
        if (timed) next = std::min(next, std::floor((settings.timeBudget_s - seconds) / perSample));
        return uint32_t(std::clamp(next, 1.0, double(settings.spp - out.spp)));
    };
    // Across ranks a failure of rank 0's (writing the images) must stop
    // the others, which wait for its decision.
    constexpr uint32_t kRankZeroFailed = ~0u;
    for (uint32_t round = 1; round > 0;) {
        rounds.render(nullptr, out.spp, round);
        out.spp += round;
        rounds.result().seconds = elapsed();
        uint32_t next = 0;
        std::exception_ptr failure;
        if (decides) try {
                out.medianRelativeError = medianRelativeError(rounds.result().film, sensor, nullptr, true);
                if (onRound) onRound(rounds.result(), out.spp);
                next = nextRound();
            } catch (...) {
                if (!rounds.acrossRanks()) throw;
                failure = std::current_exception();
                next = kRankZeroFailed;
            }
        round = rounds.acrossRanks() ? broadcastFromRankZero(next) : next;
        if (failure) std::rethrow_exception(failure);
        if (round == kRankZeroFailed) throw std::runtime_error("MPI rank 0 failed");
    }
    out.result = std::move(rounds.result());
    out.result.stats = rounds.stats();
    return out;
}

}  // namespace pl
