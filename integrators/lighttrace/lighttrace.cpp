#include "integrators/lighttrace/lighttrace.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <unordered_set>

#include "integrators/render_settings.h"
#include "runtime/distributed.h"
#include "runtime/interrupt.h"
#include "runtime/scheduler.h"

namespace pl {

const std::vector<OptionParameter<LightTraceOptions>>& lightTraceParameters() {
    using O = LightTraceOptions;
    static const std::vector<OptionParameter<O>> parameters = {
        {"particles_per_pixel", &O::particlesPerPixel, 0, 1e6, true, "must be in (0, 1e6]",
         "particles per sample (one block of light paths) for each sensor pixel"},
        {"lighttrace_hybrid", &O::hybrid, 0, 0, false, "", "printpt takes the pixels it serves better"},
        {"lighttrace_track_spacing_mfp", &O::trackSpacing_mfp, 0.01, 100, false,
         "must be in [0.01, 100] (scattering mean free paths)", "the spacing of the scoring points along tracks"},
    };
    return parameters;
}

namespace {

// Below this optical depth the transmittance to the surface is estimated
// exactly; beyond it Russian roulette ends most connections early.
constexpr float kConnectionRouletteDepth = 2.0f;
// Particles per patch, relative to particles_per_pixel, far from every
// pixel the light side scores into (no brick of theirs or next to theirs
// holds one); weighted back, so the estimate stays unbiased.
constexpr float kFarEmissionShare = 0.125f;
// Track points whose weight (sigma_s times the spacing) is below this
// connect by Russian roulette: clear resin's points (weight ~1e-5) cost no
// connections, the inks' (0.07 and up in black) keep theirs
// (docs/performance.md, "A clear block").
constexpr float kLeastTrackWeight = 0.01f;
// The relative light left at the inward normal lines' depth.
constexpr float kLineDepthOpticalDepth = 13.8f;  // e^-13.8 ~ 1e-6

const SurfaceVoxelSensor& surfaceVoxelSensorOf(const Sensor& sensor) {
    const auto* s = dynamic_cast<const SurfaceVoxelSensor*>(&sensor);
    if (!s || !s->patches())
        throw std::invalid_argument(
            "lighttrace scores into surface-voxel patches: the sensor must be \"surface_voxels\" with \"footprint\": "
            "\"patch\"");
    return *s;
}

// How deep the inward normal lines reach into the object: where the least
// extinction of the labels in the grid leaves less than 1e-6 of the light
// (at most the object's diagonal).
float lineDepthFor_mm(const Scene& scene, const RGB& leastSigmaT) {
    const Bounds3f b = scene.geometry->bounds();
    const float diagonal_mm = length(b.hi - b.lo);
    const float least = std::min(leastSigmaT[0], std::min(leastSigmaT[1], leastSigmaT[2]));
    return std::min(diagonal_mm, kLineDepthOpticalDepth / std::max(least, 1e-30f));
}

}  // namespace

LightTrace::LightTrace(const Scene& scene, const Sensor& sensor, LightTraceOptions options, VolPathOptions volpath,
                       PrintPtOptions printpt, Majorants majorants, uint64_t seed)
    : scene_(scene),
      sensor_(surfaceVoxelSensorOf(sensor)),
      patches_(*sensor_.patches()),
      options_(options),
      volpathOptions_(volpath),
      volpath_(scene, volpath, /*reentry=*/false),  // lighttrace refuses re-entry
      printpt_(scene, printpt, seed),
      majorants_(majorants),
      lightSeed_(mix64(seed ^ 0x6c69676874ULL)),
      entries_(*scene.geometry) {
    if (!(options.trackSpacing_mfp > 0.0f)) throw std::invalid_argument("lighttrace: the track spacing must be positive");
    const GridCoefficients coefficients = gridCoefficientsOf(*scene.medium);
    leastSigmaT_ = coefficients.leastSigmaT;
    const float depth_mm = lineDepthFor_mm(scene, leastSigmaT_);
    for (float fraction : {0.125f, 0.25f, 0.5f, 1.0f})
        prismLevels_.push_back(std::make_unique<PrismIndex>(scene.geometry->mesh(), depth_mm * fraction));
    const Vec3f v = scene.medium->frame().voxelSize_mm;
    for (int c = 0; c < 3; ++c) trackSpacing_mm_[c] = options.trackSpacing_mfp / coefficients.mostSigmaS[c];
    for (auto& serves : lightServes_) serves.resize(sensor_.pixelCount());
    for (size_t p = 0; p < sensor_.pixelCount(); ++p) {
        const Vec3f n = sensor_.pixels()[p].normal;
        const double crossSection_mm2 = std::abs(n.x) * v.y * v.z + std::abs(n.y) * v.x * v.z + std::abs(n.z) * v.x * v.y;
        const bool sliver = patches_.area_mm2(p) < kMinPatchFraction * crossSection_mm2;
        const bool oneResin =
            scene.medium->majorants().solidLabelAt(sensor_.pixels()[p].voxel) != MajorantGrid::kSeveralLabels;
        for (auto& serves : lightServes_) serves[p] = !sliver && !(options.hybrid && oneResin) ? 1 : 0;
    }
    decideEmissionShares();
}

std::vector<ParameterInfo> LightTrace::parameters() {
    std::vector<ParameterInfo> all = describe(lightTraceParameters());
    all.push_back(describeChoice("lighttrace_scoring", kLightTraceScoringNames,
                                 "where particles score: at their collisions or along their tracks"));
    for (const std::vector<ParameterInfo>& side : {describe(volPathParameters()), describe(printPtParameters())})
        all.insert(all.end(), side.begin(), side.end());
    return all;
}

IntegratorCapabilities LightTrace::capabilities(const RenderSettings& settings) {
    IntegratorCapabilities c;
    c.needs = {readOptions(printPtParameters(), settings.parameters).nee, true};
    c.lightPathsServeEveryPixel = true;
    c.sensors = kSurfaceVoxelPatchSensor;
    return c;
}

std::unique_ptr<Integrator> LightTrace::create(const Scene& scene, const Sensor& sensor, const RenderSettings& s) {
    LightTraceOptions options = readOptions(lightTraceParameters(), s.parameters);
    options.scoring = readChoice("lighttrace_scoring", kLightTraceScoringNames, s.parameters, options.scoring);
    return std::make_unique<LightTrace>(scene, sensor, options, readOptions(volPathParameters(), s.parameters),
                                        readOptions(printPtParameters(), s.parameters), s.majorants, s.seed);
}

void LightTrace::render(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress) const {
    if (pass.channel < 0) throw std::logic_error("lighttrace renders one channel per pass");
    const PixelShare& share = pass.share;
    const int ranks = share.acrossRanks ? Distributed::ranks() : 1, rank = share.acrossRanks ? Distributed::rank() : 0;
    for (uint32_t wave = pass.firstSample; wave < pass.firstSample + pass.count; wave += uint32_t(ranks)) {
        const int blocks = int(std::min<uint32_t>(uint32_t(ranks), pass.firstSample + pass.count - wave));
        LightBlockScores mine;
        if (rank < blocks) {
            mine.assign(pass.sensor.pixelCount());
            scoreLightBlock(pass.channel, wave + uint32_t(rank), mine, stats);
        }
        // Across ranks: by position in this rank's share; in one process:
        // by pixel.
        std::vector<LightBlockScores> light(1);
        if (share.acrossRanks) {
            const size_t pixels = pass.sensor.pixelCount();
            std::vector<std::vector<double>> scores = shareBlocksByPixel(std::move(mine.score), pixels, blocks);
            std::vector<std::vector<double>> squares = shareBlocksByPixel(std::move(mine.scoreSq), pixels, blocks);
            light.resize(size_t(blocks));
            for (size_t k = 0; k < size_t(blocks); ++k) light[k] = {std::move(scores[k]), std::move(squares[k])};
        } else {
            light[0] = std::move(mine);
        }
        for (int k = 0; k < blocks; ++k) {
            const uint32_t s = wave + uint32_t(k);
            renderPixelTiles(pass, stats, progress, 1, [&](size_t i, LabelMedium::Tracker& medium, PathStats& tileStats) {
                const size_t p = share.pixel(i);
                Rng rng = Rng::forPath(pass.seed, p, s, uint64_t(pass.channel));
                float u0 = rng.uniform(), u1 = rng.uniform();
                ChannelSample sample =
                    cameraSide(p, pass.sensor.generateRay(p, u0, u1), pass.channel, medium, rng, tileStats);
                const size_t at = share.acrossRanks ? positionInShare(uint32_t(p), ranks) : p;
                sample.value += float(light[size_t(k)].score[at]);
                sample.withinVariance = float(light[size_t(k)].scoreSq[at]);
                film.add(share.filmPixel(i), pass.channel, sample);
            });
        }
    }
}

void LightTrace::preprocess(const Sensor& sensor, const std::vector<int>& channels) {
    printpt_.preprocess(sensor, channels);
    if (!options_.hybrid) return;
    // A pixel's centre ray stands for its entries (tiles of pixels, each
    // decided by one thread; a pixel's decision depends on it alone).
    for (int c : channels)
        parallelForTiles(sensor_.pixelCount(), 256, [&](size_t begin, size_t end) {
            LabelMedium::Tracker medium(*scene_.medium, majorants_);
            for (size_t p = begin; p < end; ++p)
                if (lightServes_[c][p] && printpt_.controlsEntry(sensor_.generateRay(p, 0.5f, 0.5f), c, medium))
                    lightServes_[c][p] = 0;
        });
    decideEmissionShares();
}

void LightTrace::decideEmissionShares() {
    // Majorant bricks holding a pixel the light side scores into, per
    // channel; a patch whose brick or a neighbour of it holds one gets the
    // full share.
    auto brickKey = [](const Vec3i& brick) {
        return (uint64_t(uint32_t(brick.x + 0x100000)) << 42) | (uint64_t(uint32_t(brick.y + 0x100000)) << 21) |
               uint64_t(uint32_t(brick.z + 0x100000));
    };
    for (int c = 0; c < 3; ++c) {
        std::unordered_set<uint64_t> lit;
        for (size_t p = 0; p < sensor_.pixelCount(); ++p)
            if (lightServes_[c][p]) lit.insert(brickKey(MajorantGrid::brickOf(sensor_.pixels()[p].voxel)));
        nearLitPixels_[c].assign(sensor_.pixelCount(), 0);
        for (size_t p = 0; p < sensor_.pixelCount(); ++p) {
            const Vec3i b = MajorantGrid::brickOf(sensor_.pixels()[p].voxel);
            for (int dz = -1; dz <= 1 && !nearLitPixels_[c][p]; ++dz)
                for (int dy = -1; dy <= 1 && !nearLitPixels_[c][p]; ++dy)
                    for (int dx = -1; dx <= 1; ++dx)
                        if (lit.count(brickKey({b.x + dx, b.y + dy, b.z + dz}))) {
                            nearLitPixels_[c][p] = 1;
                            break;
                        }
        }
    }
}

float LightTrace::emissionShare(int channel, size_t pixel) const {
    return nearLitPixels_[channel][pixel] ? 1.0f : kFarEmissionShare;
}

size_t LightTrace::cameraOnlyPixels(int channel) const {
    return size_t(std::count(lightServes_[channel].begin(), lightServes_[channel].end(), uint8_t(0)));
}

ChannelSample LightTrace::cameraSide(size_t pixel, Ray ray, int channel, LabelMedium::Tracker& medium, Rng& rng,
                                     PathStats& stats) const {
    if (!lightServes_[channel][pixel]) return printpt_.Li(ray, channel, medium, rng, stats);
    const Geometry& geometry = *scene_.geometry;
    const float Le = scene_.environment[channel];
    stats.paths += 1;
    // The light side adds its block's score and that score's variance; the
    // camera side's own random part (the transmittance and the far
    // boundary's light) is pooled over the entries into the same label
    // where a pixel's are all equal (Film).
    ChannelSample sample;
    sample.hasWithinVariance = true;
    auto entry = geometry.intersect(ray);
    if (!entry) {
        sample.value = Le;
        return sample;
    }
    // The sensor's ray runs along the patch's inward normal: the light
    // leaving along the normal is reflected (F at normal incidence) or comes
    // straight along the line from inside.
    const float F = fresnelDielectric(-dot(ray.d, entry->ng), scene_.ior);
    sample.value = F * Le;
    const Ray inward = geometry.spawnRay(entry->p, entry->ng, ray.d);
    sample.poolKey = entryPoolKeyOfPart(channel, medium.labelAt(scene_.medium->voxelAt(inward.o)));
    sample.poolWhereFlat = true;
    auto far = geometry.intersectFromInside(inward);
    if (!far) {
        stats.leaks += 1;
        return sample;
    }
    // Unscattered along the first segment (the light side has the rest).
    const Ray fromSurface{inward.o - inward.d * inward.mediumBefore_mm, inward.d};
    const float T = medium.transmittance(fromSurface, far->t + inward.mediumBefore_mm, channel,
                                         TransmittanceRoulette{kConnectionRouletteDepth, &rng});
    if (T <= 0.0f) return sample;
    // At the far boundary: the environment transmitted in, or what
    // arrives there along the mirror direction, reflected (volpath).
    const Vec3f n = -far->ns;  // facing against the ray
    const float Ffar = fresnelDielectric(-dot(inward.d, n), 1.0f / scene_.ior);
    float Lfar = (1.0f - Ffar) * Le;
    if (rng.uniform() < Ffar)
        Lfar += volpath_.Li(reflectedInside(geometry, inward.d, *far), channel, medium, rng, stats).value;
    sample.residual = (1.0f - F) * T * Lfar;
    sample.value += sample.residual;
    return sample;
}

size_t LightTrace::blockWorkers() {
    return std::min<size_t>(kBlockParts, size_t(tbb::this_task_arena::max_concurrency()));
}

size_t LightTrace::mostTalliesAlive() { return std::min<size_t>(kBlockParts, 2 * blockWorkers()); }

void LightTrace::ParticleTally::reach(uint32_t pixel) {
    // Widened by half its size, and by at least 4096 pixels (a particle's
    // first scores spread over its neighbours: few copies from the start).
    const size_t slack = std::max<size_t>(score.size() / 2, 4096);
    const bool empty = score.empty();
    size_t lo = empty ? pixel : firstPixel, hi = empty ? size_t(pixel) + 1 : firstPixel + score.size();
    if (pixel <= lo) lo = pixel >= slack ? pixel - slack : 0;
    if (size_t(pixel) + 1 >= hi) hi = std::min(size_t(pixel) + 1 + slack, sensorPixels);
    std::vector<double> widerScore(hi - lo, 0.0);
    std::vector<float> widerSq(hi - lo, 0.0f);
    if (!empty) {
        std::copy(score.begin(), score.end(), widerScore.begin() + std::ptrdiff_t(firstPixel - lo));
        std::copy(scoreSq.begin(), scoreSq.end(), widerSq.begin() + std::ptrdiff_t(firstPixel - lo));
    }
    firstPixel = lo;
    score = std::move(widerScore);
    scoreSq = std::move(widerSq);
}

void LightTrace::ParticleTally::endParticle() {
    // Each pixel's whole score from the particle, squared.
    std::sort(particle.begin(), particle.end());
    for (size_t i = 0; i < particle.size();) {
        const uint32_t pixel = particle[i].first;
        double sum = 0;
        for (; i < particle.size() && particle[i].first == pixel; ++i) sum += particle[i].second;
        scoreSq[pixel - firstPixel] += float(sum * sum);
    }
    particle.clear();
}

void LightTrace::scoreLightBlock(int channel, uint32_t sample, LightBlockScores& block, PathStats& stats) const {
    const double Le = scene_.environment[channel];
    // Nothing to score into: no particles.
    if (!(Le > 0.0) || cameraOnlyPixels(channel) == sensor_.pixelCount()) return;
    const double particlesPerPixel = options_.particlesPerPixel;
    // Entry points are stratified by patch where the patches tile the mesh:
    // every patch receives its share of each block's particles (whole
    // particles, the fraction by a coin), so the number entering near a
    // voxel does not fluctuate. Each carries the power the environment
    // sends into its patch, Le pi A, over the expected count. Elsewhere
    // they enter uniformly over the mesh.
    const bool stratified = patches_.unassignedArea_mm2() == 0.0;
    // What the block's parts share out: pixels (stratified) or particles.
    const uint64_t units = stratified ? sensor_.pixelCount()
                                      : std::max<uint64_t>(1, uint64_t(std::llround(particlesPerPixel * double(sensor_.pixelCount()))));
    const size_t pixels = block.score.size();
    // Parts are handed out in order to as many workers as run at once, and
    // each part's tally is added to the block as soon as the parts before
    // it are: in part order (the same bits whatever the threads). A part
    // starts only within mostTalliesAlive() of the next to be added, so
    // that many tallies at most are alive whatever a slow part holds up.
    std::atomic<size_t> nextPart{0};
    std::mutex merging;
    std::condition_variable merged;
    size_t nextToMerge = 0;
    bool stopped = false;
    std::map<size_t, ParticleTally> finished;
    auto mergeInOrder = [&](size_t part, ParticleTally tally, const PathStats& partStats) {
        std::lock_guard<std::mutex> lock(merging);
        stats += partStats;
        finished.emplace(part, std::move(tally));
        for (auto it = finished.find(nextToMerge); it != finished.end(); it = finished.find(++nextToMerge)) {
            const ParticleTally& t = it->second;
            for (size_t k = 0; k < t.score.size(); ++k) {
                block.score[t.firstPixel + k] += t.score[k];
                block.scoreSq[t.firstPixel + k] += double(t.scoreSq[k]);
            }
            finished.erase(it);
        }
        merged.notify_all();
    };
    const size_t alive = mostTalliesAlive();
    parallelForTiles(blockWorkers(), 1, [&](size_t, size_t) {
        LabelMedium::Tracker medium(*scene_.medium, majorants_);
        for (size_t part = nextPart++; part < kBlockParts; part = nextPart++) {
            {
                // The parts before this one hold no thread waiting here (the
                // earliest waiting part's predecessors are all running), so
                // this wait ends.
                std::unique_lock<std::mutex> lock(merging);
                merged.wait(lock, [&] { return stopped || part < nextToMerge + alive; });
                if (stopped) return;
            }
            ParticleTally tally(pixels);
            PathStats partStats;
            std::vector<SurfacePatches::Piece> pieces;  // the patch particles enter, cut once for them
            for (uint64_t i = units * part / kBlockParts; i < units * (part + 1) / kBlockParts; ++i) {
                if (interruptRequested()) {
                    std::lock_guard<std::mutex> lock(merging);
                    stopped = true;
                    merged.notify_all();
                    return;
                }
                Rng rng = Rng::forPath(lightSeed_, i, sample, uint64_t(channel));
                if (!stratified) {
                    const SurfaceHit entry = entries_.sample(rng);
                    traceParticle(channel, entry, Le * kPi * entries_.area_mm2() / double(units), medium, rng, tally,
                                  partStats);
                    continue;
                }
                if (patches_.area_mm2(i) == 0.0) continue;  // an empty patch: nothing enters there
                const double expected = particlesPerPixel * emissionShare(channel, i);
                const double whole = std::floor(expected);
                const int count = int(whole) + (rng.uniform() < expected - whole ? 1 : 0);
                const double weight = Le * kPi * patches_.area_mm2(i) / expected;
                if (count > 0) patches_.piecesOf(i, pieces);
                for (int j = 0; j < count; ++j) {
                    const float u0 = rng.uniform(), u1 = rng.uniform();
                    const auto x = patches_.sample(pieces, u0, u1);  // not empty (above)
                    traceParticle(channel, scene_.geometry->pointAt(x->prim, x->p), weight, medium, rng, tally,
                                  partStats);
                }
            }
            mergeInOrder(part, std::move(tally), partStats);
        }
    });
}

void LightTrace::traceParticle(int channel, const SurfaceHit& entry, double weight, LabelMedium::Tracker& medium,
                               Rng& rng, ParticleTally& tally, PathStats& stats) const {
    const Geometry& geometry = *scene_.geometry;
    const ChannelLut& lut = scene_.medium->lut(channel);
    SingleChannelPath path{&lut, channel, scene_.environment[channel]};

    // Light leaving along the normal: transmitted out, and radiance / n^2
    // (the path tracers' unit inside).
    const float exitFactor = (1.0f - fresnelDielectric(1.0f, scene_.ior)) / (scene_.ior * scene_.ior);
    const float visibilityTolerance_mm = geometry.rayEpsilon_mm();
    const float leastSigmaT = leastSigmaT_[channel];
    // The transmittance to a surface point s_mm away is at most
    // exp(-leastSigmaT s): connections are played by Russian roulette on
    // that bound before any work (survival exp(-(bound's depth -
    // kConnectionRouletteDepth))), and the survivors' transmittance
    // estimates carry the log of the scale (TransmittanceRoulette::logScale).
    auto rouletteLogScale = [&](float distance_mm) {
        return std::max(0.0f, leastSigmaT * distance_mm - kConnectionRouletteDepth);
    };
    // The connection roulette at y: one uniform number u plays every
    // line's roulette: line s survives if u < exp(-logScale(s)), still with
    // that probability on its own, and only lines shallower than sMax can.
    // Every line's surface point is at least the clearance away, so y
    // connects nowhere when u loses at the clearance.
    struct ConnectionRoulette {
        float u;
        float sMax_mm;
    };
    auto connectionRoulette = [&](const Point3f& y) -> std::optional<ConnectionRoulette> {
        const float u = rng.uniform();
        const float nearLogScale = scene_.clearance ? rouletteLogScale(scene_.clearance->at(y)) : 0.0f;
        if (!(u < std::exp(-nearLogScale))) return std::nullopt;
        return ConnectionRoulette{u, leastSigmaT > 0.0f ? (kConnectionRouletteDepth - std::log(u)) / leastSigmaT
                                                        : std::numeric_limits<float>::infinity()};
    };
    // Scores the light scattered at y towards every line through y, times
    // weightFactor.
    auto score = [&](const Point3f& y, const Vec3f& dIn, Label label, float weightFactor,
                     const SingleChannelPath& p, ConnectionRoulette roulette) {
        const PrismIndex* prisms = prismLevels_.back().get();
        for (const auto& level : prismLevels_)
            if (level->depth_mm() >= roulette.sMax_mm) {
                prisms = level.get();
                break;
            }
        prisms->forEachLine(y, [&](const PrismIndex::Line& line) {
            const float logScale = rouletteLogScale(line.s_mm);
            if (!(roulette.u < std::exp(-logScale))) return;
            auto pixel = patches_.pixelAt(line.prim, line.x_mm);
            if (!pixel || !lightServes_[channel][*pixel]) return;
            const Ray toSurface{y, line.normal};
            const float T = medium.transmittance(toSurface, line.s_mm, channel,
                                                 TransmittanceRoulette{kConnectionRouletteDepth, &rng, logScale});
            if (T <= 0.0f) return;
            // The line's first segment: nothing between y and the patch.
            auto hit = geometry.intersect(toSurface, line.s_mm + visibilityTolerance_mm);
            if (!hit || hit->t < line.s_mm - visibilityTolerance_mm) return;
            const float phase = hgPhase(dot(dIn, line.normal), lut.g[label]);
            tally.add(*pixel, weight * double(weightFactor * p.beta * phase * T * exitFactor) / patches_.area_mm2(*pixel));
        });
    };
    const bool alongTracks = options_.scoring == LightTraceOptions::Scoring::Tracks;
    auto onCollision = [&](const Point3f& y, const Vec3f& dIn, Label label, const SingleChannelPath& p) {
        if (alongTracks) return;
        if (auto roulette = connectionRoulette(y)) score(y, dIn, label, 1.0f, p, *roulette);
    };
    auto onFlight = [&](const Ray& r, float tEnd_mm, const SingleChannelPath& p) {
        if (!alongTracks) return;
        const float spacing_mm = trackSpacing_mm_[channel];
        const float offset = rng.uniform();
        for (int64_t k = 0;; ++k) {
            const float t = (float(k) + offset) * spacing_mm;  // no round-off carried from point to point
            if (!(t < tEnd_mm)) break;
            const Point3f y = r.at(t);
            auto roulette = connectionRoulette(y);
            if (!roulette) continue;
            const Label label = medium.labelAt(scene_.medium->voxelAt(y));
            // A point's weight sigma_s h is the spacing in mean free paths
            // in the most scattering label. Where it is far below (clear
            // resin), the point connects with probability pointWeight /
            // kLeastTrackWeight instead, so that negligible weights cost no
            // connections.
            const float pointWeight = lut.sigmaT_perMm[label] * lut.albedo[label] * spacing_mm;
            const float keep = std::min(1.0f, pointWeight / kLeastTrackWeight);
            if (keep > 0.0f && rng.uniform() < keep) score(y, r.d, label, pointWeight / keep, p, *roulette);
        }
    };
    walkParticleIn(scene_, volpathOptions_, entry, path, medium, rng, stats, onFlight, onCollision);
    tally.endParticle();
}

}  // namespace pl
