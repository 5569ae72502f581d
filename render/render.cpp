#include "render/render.h"

#include <algorithm>
#include <chrono>
#include <optional>
#include <stdexcept>
#include <string>

#include "runtime/distributed.h"
#include "render/registry.h"
#include "runtime/interrupt.h"
#include "runtime/progress.h"

namespace pl {

namespace {

// Passes: one per channel, or one (marked -1) for all three.
std::vector<int> passesOf(const RenderSettings& settings) {
    return rendersChannelsInOnePass(settings) ? std::vector<int>{-1} : settings.channels;
}

}  // namespace

std::unique_ptr<Integrator> makeIntegrator(const Scene& scene, const Sensor& sensor, const RenderSettings& settings) {
    std::unique_ptr<Integrator> integrator =
        integratorKindOf(settings).factory.create(scene, sensor, settings);
    if (!rendersChannelsInOnePass(settings)) integrator->preprocess(sensor, passesOf(settings));
    return integrator;
}

void renderSamples(const Integrator& integrator, const Scene& scene, const Sensor& sensor,
                   const RenderSettings& settings, const PixelShare& share, uint32_t firstSample, uint32_t count,
                   RenderResult& result, bool lastSamples, PathFootprints* footprints,
                   const CoupledSampling* coupled) {
    // A deterministic estimator's samples are all the same: one says all.
    if (capabilitiesOf(settings).deterministic) {
        if (firstSample > 0) return;
        count = std::min(count, 1u);
    }
    auto start = std::chrono::steady_clock::now();
    const size_t n = share.size(sensor.pixelCount());
    const std::vector<int> passes = passesOf(settings);
    ProgressBar progress(uint64_t(n) * passes.size() * count, "rendering", settings.showProgress);
    for (int channel : passes) {
        const auto passStart = std::chrono::steady_clock::now();
        for (int c = 0; c < kChannels; ++c)
            if (channel < 0 || c == channel) result.film.openChannel(c);
        const RenderPass pass{scene,   sensor,        share,          firstSample, count,
                              channel, settings.seed, settings.majorants, settings.channelSampling, footprints, coupled};
        integrator.render(pass, result.film, result.stats, progress);
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
    if (!capabilitiesOf(settings).threeChannelsInOnePath) return false;
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
        if (share.acrossRanks && !capabilitiesOf(settings).lightPathsServeEveryPixel) {
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
