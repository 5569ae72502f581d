#include "integrators/render.h"

#include <chrono>
#include <mutex>

#include "core/interrupt.h"
#include "core/progress.h"
#include "core/scheduler.h"

namespace pl {

void renderSamples(const Scene& scene, const Sensor& sensor, const RenderSettings& settings,
                   const std::vector<uint32_t>& pixels, uint32_t firstSample, uint32_t count, RenderResult& result) {
    auto start = std::chrono::steady_clock::now();
    std::unique_ptr<Integrator> integrator;
    if (settings.integrator == "printpt") integrator = std::make_unique<PrintPt>(scene, settings.printpt);
    else integrator = std::make_unique<VolPath>(scene, settings.volpath);

    const size_t n = pixels.empty() ? sensor.pixelCount() : pixels.size();
    ProgressBar progress(uint64_t(n) * settings.channels.size(), "rendering", settings.showProgress);
    std::mutex statsMutex;
    // One pass per channel (Brecka renders R, G and B as separate images).
    for (int channel : settings.channels) {
        parallelForTiles(n, 64, [&](size_t begin, size_t end) {
            LabelMedium::Sampler medium(*scene.medium);
            PathStats stats;
            for (size_t i = begin; i < end; ++i) {
                size_t p = pixels.empty() ? i : pixels[i];
                for (uint32_t s = firstSample; s < firstSample + count; ++s) {
                    if (interruptRequested()) return;  // Ctrl-C: the film is discarded by the caller
                    // The path's random stream depends only on (seed, pixel, sample, channel).
                    Rng rng = Rng::forPath(settings.seed, p, s, uint64_t(channel));
                    float u0 = rng.uniform(), u1 = rng.uniform();
                    Ray ray = sensor.generateRay(p, u0, u1);
                    result.film.add(p, channel, integrator->Li(ray, channel, medium, rng, stats));
                }
            }
            progress.advance(end - begin);
            std::lock_guard<std::mutex> lock(statsMutex);
            result.stats += stats;
        });
    }
    throwIfInterrupted();
    progress.finish();
    result.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

RenderResult render(const Scene& scene, const Sensor& sensor, const RenderSettings& settings) {
    RenderResult result{Film(sensor.pixelCount()), {}, 0};
    renderSamples(scene, sensor, settings, {}, 0, settings.spp, result);
    return result;
}

}  // namespace pl
