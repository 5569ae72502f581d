#include "integrators/integrator.h"

#include "integrators/render_settings.h"

namespace pl {

void PixelIntegrator::render(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress) const {
    if (pass.coupled) {
        // A tracker of the previous labels per tile, beside the current's.
        renderTiles(pass, stats, progress, pass.count, [&](size_t begin, size_t end, PathStats& tileStats) {
            LabelMedium::Tracker medium(*pass.scene.medium, pass.majorants);
            LabelMedium::Tracker before(*pass.coupled->previous, pass.majorants);
            for (size_t i = begin; i < end; ++i) {
                if (interruptRequested()) return false;
                renderPixelPairs(pass, film, i, pass.share.pixel(i), medium, before, tileStats);
            }
            return true;
        });
        return;
    }
    renderPixelTiles(pass, stats, progress, pass.count, [&](size_t i, LabelMedium::Tracker& medium, PathStats& tileStats) {
        const size_t p = pass.share.pixel(i);
        if (!pass.footprints) {
            renderPixel(pass, film, i, p, medium, tileStats);
            return;
        }
        // What this pixel's paths read of the labels.
        thread_local LabelReads reads;
        reads.clear();
        medium.recordReads(&reads);
        renderPixel(pass, film, i, p, medium, tileStats);
        medium.recordReads(nullptr);
        pass.footprints->add(p, reads);
    });
}

void PixelIntegrator::renderPixel(const RenderPass& pass, Film& film, size_t i, size_t p, LabelMedium::Tracker& medium,
                                  PathStats& tileStats) const {
    const PixelShare& share = pass.share;
    const uint32_t endSample = pass.firstSample + pass.count;
    // Hero channels go round the samples from a random start per
    // pixel (independent of the paths): each sample's hero is
    // uniform, and every three samples of a pixel have all three.
    const uint32_t heroOffset = uint32_t(mix64(mix64(pass.seed ^ 0x6865726fULL) ^ p) % 3);
    // Stratified heroes: samples 3j, 3j+1, 3j+2 go to the film as one group.
    double group[3] = {0, 0, 0};
    uint32_t inGroup = 0;
    for (uint32_t s = pass.firstSample; s < endSample; ++s) {
        if (interruptRequested()) return;  // Ctrl-C: the film is discarded by the caller
        // The path's random stream depends only on (seed, pixel, sample, channel or 3 for all).
        Rng rng = Rng::forPath(pass.seed, p, s, uint64_t(pass.channel < 0 ? 3 : pass.channel));
        float u0 = rng.uniform(), u1 = rng.uniform();
        Ray ray = pass.sensor.generateRay(p, u0, u1);
        if (pass.channel >= 0) {
            film.add(share.filmPixel(i), pass.channel, Li(ray, pass.channel, medium, rng, tileStats));
            continue;
        }
        int hero = int((s + heroOffset) % 3);
        RGB L = LiRGB(ray, pass.channelSampling, hero, medium, rng, tileStats);
        for (int c = 0; c < 3; ++c) group[c] += L[c];
        ++inGroup;
        const bool stratified = pass.channelSampling == ChannelSampling::Hero;
        if (!stratified || s % 3 == 2 || s + 1 == endSample) {
            for (int c = 0; c < 3; ++c) film.addGroup(share.filmPixel(i), c, group[c], inGroup);
            group[0] = group[1] = group[2] = 0;
            inGroup = 0;
        }
    }
}

void PixelIntegrator::renderPixelPairs(const RenderPass& pass, Film& film, size_t i, size_t p,
                                       LabelMedium::Tracker& medium, LabelMedium::Tracker& before,
                                       PathStats& tileStats) const {
    const CoupledSampling& coupled = *pass.coupled;
    const int c = pass.channel;
    if (c < 0) throw std::logic_error("samples in pairs take one pass per channel");
    thread_local LabelReads reads;
    for (uint32_t s = pass.firstSample; s < pass.firstSample + pass.count; ++s) {
        if (interruptRequested()) return;
        Rng rng = Rng::forPath(pass.seed, p, s, uint64_t(c));
        const float u0 = rng.uniform(), u1 = rng.uniform();
        const Ray ray = pass.sensor.generateRay(p, u0, u1);
        Rng rngBefore = rng;
        reads.clear();
        medium.recordReads(&reads);
        const ChannelSample f = Li(ray, c, medium, rng, tileStats);
        medium.recordReads(nullptr);
        film.add(pass.share.filmPixel(i), c, f);
        // The same path under the previous labels, unless it read nothing that changed.
        ChannelSample difference;
        if (coupled.changes->metBy(reads)) {
            difference.value = f.value - Li(ray, c, before, rngBefore, tileStats).value;
            (*coupled.tracedTwice)[p] += 1;
        }
        coupled.differences->add(pass.share.filmPixel(i), c, difference);
        const float w = (*coupled.weights)[p][c];
        coupled.combined->add(pass.share.filmPixel(i), c, ChannelSample{(1 - w) * f.value + w * difference.value});
    }
}

std::string refusalWithoutReentry(const char* name, const RenderSettings& settings) {
    return settings.reentry
               ? std::string(name) + " does not trace re-entry; the scene asks for \"reentry\": true"
               : std::string();
}

}  // namespace pl
