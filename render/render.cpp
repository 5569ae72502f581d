#include "render/render.h"

#include <algorithm>
#include <chrono>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>

#include "runtime/distributed.h"
#include "render/registry.h"
#include "runtime/interrupt.h"
#include "runtime/progress.h"
#include "runtime/scheduler.h"

namespace pl {

namespace {

// Passes: one per channel, or one (marked -1) for all three.
std::vector<int> passesOf(const RenderSettings& settings) {
    return rendersChannelsInOnePass(settings) ? std::vector<int>{-1} : settings.channels;
}

// One channel's samples with light paths (Integrator::scoreLightBlock):
// sample by sample, the block of light paths, then every pixel's camera
// sample plus what the block scored there, with the block's own estimate
// of that score's variance. Across MPI ranks the samples
// go in waves of one block per rank, each rank receiving every block's
// scores at its own pixels (runtime/distributed.h): a pixel's samples are
// the same sums in the same order as in one process.
void renderWithLightPaths(const Integrator& integrator, const Scene& scene, const Sensor& sensor,
                          const RenderSettings& settings, const PixelShare& share, uint32_t firstSample,
                          uint32_t count, int channel, ProgressBar& progress, RenderResult& result) {
    const size_t n = share.size(sensor.pixelCount());
    const int ranks = share.acrossRanks ? Distributed::ranks() : 1, rank = share.acrossRanks ? Distributed::rank() : 0;
    std::mutex statsMutex;
    for (uint32_t wave = firstSample; wave < firstSample + count; wave += uint32_t(ranks)) {
        const int blocks = int(std::min<uint32_t>(uint32_t(ranks), firstSample + count - wave));
        LightBlockScores mine;
        if (rank < blocks) {
            mine.assign(sensor.pixelCount());
            integrator.scoreLightBlock(channel, wave + uint32_t(rank), mine, result.stats);
        }
        // Across ranks: by position in this rank's share; in one process:
        // by pixel.
        std::vector<LightBlockScores> light(1);
        if (share.acrossRanks) {
            const size_t pixels = sensor.pixelCount();
            std::vector<std::vector<double>> scores = shareBlocksByPixel(std::move(mine.score), pixels, blocks);
            std::vector<std::vector<double>> squares = shareBlocksByPixel(std::move(mine.scoreSq), pixels, blocks);
            light.resize(size_t(blocks));
            for (size_t k = 0; k < size_t(blocks); ++k) light[k] = {std::move(scores[k]), std::move(squares[k])};
        } else {
            light[0] = std::move(mine);
        }
        for (int k = 0; k < blocks; ++k) {
            const uint32_t s = wave + uint32_t(k);
            parallelForTiles(n, 64, [&](size_t begin, size_t end) {
                LabelMedium::Tracker medium(*scene.medium, settings.majorants);
                PathStats stats;
                for (size_t i = begin; i < end; ++i) {
                    if (interruptRequested()) return;
                    const size_t p = share.pixel(i);
                    Rng rng = Rng::forPath(settings.seed, p, s, uint64_t(channel));
                    float u0 = rng.uniform(), u1 = rng.uniform();
                    ChannelSample sample =
                        integrator.cameraSide(p, sensor.generateRay(p, u0, u1), channel, medium, rng, stats);
                    const size_t at = share.acrossRanks ? positionInShare(uint32_t(p), ranks) : p;
                    sample.value += float(light[size_t(k)].score[at]);
                    sample.withinVariance = float(light[size_t(k)].scoreSq[at]);
                    result.film.add(share.filmPixel(i), channel, sample);
                }
                progress.advance(end - begin);
                std::lock_guard<std::mutex> lock(statsMutex);
                result.stats += stats;
            });
        }
    }
}

}  // namespace

std::unique_ptr<Integrator> makeIntegrator(const Scene& scene, const Sensor& sensor, const RenderSettings& settings,
                                           std::shared_ptr<HalfSpaceMeans> controlMeans) {
    std::unique_ptr<Integrator> integrator = integratorKindOf(settings).make(scene, sensor, settings, std::move(controlMeans));
    if (!rendersChannelsInOnePass(settings)) integrator->preprocess(sensor, passesOf(settings));
    return integrator;
}

PixelShare PixelShare::ofThisRank(size_t pixelCount) {
    if (Distributed::ranks() == 1) return {};
    return {pixelsOfRank(pixelCount, Distributed::rank(), Distributed::ranks()), true};
}

void renderSamples(const Integrator& integrator, const Scene& scene, const Sensor& sensor,
                   const RenderSettings& settings, const PixelShare& share, uint32_t firstSample, uint32_t count,
                   RenderResult& result, bool lastSamples) {
    // A deterministic estimator's samples are all the same: one says all.
    if (integratorKindOf(settings).deterministic) {
        if (firstSample > 0) return;
        count = std::min(count, 1u);
    }
    auto start = std::chrono::steady_clock::now();
    const size_t n = share.size(sensor.pixelCount());
    const std::vector<int> passes = passesOf(settings);
    ProgressBar progress(uint64_t(n) * passes.size() * count, "rendering", settings.showProgress);
    std::mutex statsMutex;
    for (int channel : passes) {
        const auto passStart = std::chrono::steady_clock::now();
        for (int c = 0; c < kChannels; ++c)
            if (channel < 0 || c == channel) result.film.openChannel(c);
        if (integrator.scoresLightPaths())
            renderWithLightPaths(integrator, scene, sensor, settings, share, firstSample, count, channel, progress,
                                 result);
        else parallelForTiles(n, 64, [&](size_t begin, size_t end) {
            LabelMedium::Tracker medium(*scene.medium, settings.majorants);
            PathStats stats;
            for (size_t i = begin; i < end; ++i) {
                const size_t p = share.pixel(i);
                // Hero channels go round the samples from a random start per
                // pixel (independent of the paths): each sample's hero is
                // uniform, and every three samples of a pixel have all three.
                const uint32_t heroOffset = uint32_t(mix64(mix64(settings.seed ^ 0x6865726fULL) ^ p) % 3);
                // Stratified heroes: samples 3j, 3j+1, 3j+2 go to the film as one group.
                double group[3] = {0, 0, 0};
                uint32_t inGroup = 0;
                for (uint32_t s = firstSample; s < firstSample + count; ++s) {
                    if (interruptRequested()) return;  // Ctrl-C: the film is discarded by the caller
                    // The path's random stream depends only on (seed, pixel, sample, channel or 3 for all).
                    Rng rng = Rng::forPath(settings.seed, p, s, uint64_t(channel < 0 ? 3 : channel));
                    float u0 = rng.uniform(), u1 = rng.uniform();
                    Ray ray = sensor.generateRay(p, u0, u1);
                    if (channel >= 0) {
                        result.film.add(share.filmPixel(i), channel, integrator.Li(ray, channel, medium, rng, stats));
                        continue;
                    }
                    int hero = int((s + heroOffset) % 3);
                    RGB L = integrator.LiRGB(ray, settings.channelSampling, hero, medium, rng, stats);
                    for (int c = 0; c < 3; ++c) group[c] += L[c];
                    ++inGroup;
                    const bool stratified = settings.channelSampling == ChannelSampling::Hero;
                    if (!stratified || s % 3 == 2 || s + 1 == firstSample + count) {
                        for (int c = 0; c < 3; ++c) result.film.addGroup(share.filmPixel(i), c, group[c], inGroup);
                        group[0] = group[1] = group[2] = 0;
                        inGroup = 0;
                    }
                }
            }
            progress.advance((end - begin) * count);
            std::lock_guard<std::mutex> lock(statsMutex);
            result.stats += stats;
        });
        if (channel >= 0)
            result.passSeconds[channel] +=
                float(std::chrono::duration<double>(std::chrono::steady_clock::now() - passStart).count());
        // Settled as soon as its pass ends (collective across ranks, so
        // even when interrupted).
        if (lastSamples && channel >= 0 && share.filmOfShare)
            settleShareAcrossRanks(result.film, channel, sensor, share.pixels);
        else if (lastSamples && channel >= 0 && !share.acrossRanks && !interruptRequested())
            result.film.settleChannel(channel, &sensor);
    }
    if (share.filmOfShare && lastSamples)
        for (int c = 0; c < kChannels; ++c)
            if (!result.film.settled(c)) settleShareAcrossRanks(result.film, c, sensor, share.pixels);
    throwIfInterrupted();
    progress.finish();
    if (!share.acrossRanks) {  // across ranks: rank 0, once gathered
        if (lastSamples)
            for (int c = 0; c < kChannels; ++c) result.film.settleChannel(c, &sensor);
        else
            result.film.poolErrors(&sensor);
    }
    result.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

bool rendersChannelsInOnePass(const RenderSettings& settings) {
    if (settings.channelSampling == ChannelSampling::Separate || settings.channels.size() != 3) return false;
    if (!integratorKindOf(settings).threeChannelsInOnePath(settings)) return false;
    bool seen[3] = {false, false, false};
    for (int c : settings.channels) seen[c] = true;
    return seen[0] && seen[1] && seen[2];
}

PathStats gatherShares(RenderResult& result, const PixelShare& share, const Sensor& sensor) {
    PathStats all = result.stats;
    if (!share.acrossRanks) return all;
    if (share.filmOfShare) {
        Film whole(Distributed::rank() == 0 ? sensor.pixelCount() : 0, false);
        gatherSettledOnRankZero(result.film, share.pixels, whole, all);
        result.film = std::move(whole);
        return all;
    }
    gatherOnRankZero(result.film, all, share.pixels);
    if (Distributed::rank() == 0) result.film.poolErrors(&sensor);
    return all;
}

namespace {
// Pixels per chunk of work stealing across ranks: long enough that asking
// rank 0 for the next (a round trip) is cheap beside rendering it.
constexpr size_t kClaimedChunkPixels = 1024;

// Across ranks, for estimators that render each pixel alone: chunks of
// pixels claimed from rank 0 until none are left (ChunkDealer), each
// rendered whole. Returns the pixels this rank rendered.
std::vector<uint32_t> renderClaimedChunks(const Integrator& integrator, const Scene& scene, const Sensor& sensor,
                                          const RenderSettings& settings, RenderResult& result) {
    RenderSettings chunkSettings = settings;
    chunkSettings.showProgress = false;  // a bar per chunk says nothing
    const size_t n = sensor.pixelCount();
    ChunkDealer dealer((n + kClaimedChunkPixels - 1) / kClaimedChunkPixels);
    std::vector<uint32_t> rendered;
    while (const std::optional<size_t> chunk = dealer.next()) {
        PixelShare pixels{{}, true};
        for (size_t p = *chunk * kClaimedChunkPixels; p < std::min(n, (*chunk + 1) * kClaimedChunkPixels); ++p)
            pixels.pixels.push_back(uint32_t(p));
        renderSamples(integrator, scene, sensor, chunkSettings, pixels, 0, settings.spp, result);
        rendered.insert(rendered.end(), pixels.pixels.begin(), pixels.pixels.end());
    }
    return rendered;
}
}  // namespace

RenderResult render(const Scene& scene, const Sensor& sensor, const RenderSettings& settings, bool acrossRanks) {
    const auto start = std::chrono::steady_clock::now();
    PixelShare share{{}, acrossRanks && Distributed::ranks() > 1};  // its pixels: below
    // Each channel is opened as its pass starts and settled as it ends
    // (renderSamples): in one process, and on the ranks with light paths,
    // whose films hold their shares alone. Claimed chunks are gathered whole.
    RenderResult result{Film(sensor.pixelCount(), false)};
    const double communicatedBefore = Distributed::secondsCommunicating();
    // Across ranks every rank has its integrator before any deals or waits.
    std::unique_ptr<Integrator> integrator;
    auto make = [&] { integrator = makeIntegrator(scene, sensor, settings); };
    auto work = [&] {
        // Light paths serve every pixel: their shares are fixed (the
        // blocks' scores go to each pixel's rank); other estimators steal.
        if (share.acrossRanks && !integrator->scoresLightPaths()) {
            result.film = Film(sensor.pixelCount());
            share.pixels = renderClaimedChunks(*integrator, scene, sensor, settings, result);
            return;
        }
        if (share.acrossRanks) {
            share = PixelShare::ofThisRank(sensor.pixelCount());
            share.filmOfShare = true;
            result.film = Film(share.pixels.size(), false);
        }
        renderSamples(*integrator, scene, sensor, settings, share, 0, settings.spp, result, true);
    };
    runOnEveryRank(make, share.acrossRanks);
    runOnEveryRank(work, share.acrossRanks);
    result.stats = gatherShares(result, share, sensor);
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (share.acrossRanks)
        result.communicationShare =
            gatherOnRankZero((Distributed::secondsCommunicating() - communicatedBefore) / result.seconds);
    return result;
}

}  // namespace pl
