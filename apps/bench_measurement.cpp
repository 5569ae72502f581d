#include "apps/bench_measurement.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "compare/render_error.h"
#include "compare/surface_reflectances.h"
#include "core/input_error.h"
#include "render/progressive_render.h"
#include "render/registry.h"
#include "runtime/distributed.h"

namespace pl {

namespace {

// The samples of one render for a budget, from the time one sample took.
uint32_t samplesFor(const RenderSettings& s, double budget, double perSpp, const Arguments& args, bool self,
                    uint32_t selfSpp, bool acrossRanks) {
    uint32_t spp = capabilitiesOf(s).deterministic ? 1u : uint32_t(std::max(1.0, std::round(budget / perSpp)));
    if (acrossRanks) spp = broadcastFromRankZero(spp);  // rank 0's clock decides
    if (self && args.has("--spp")) spp = selfSpp;
    if (self) spp = std::max(spp, selfSpp);
    // Hero channels go round groups of three samples, whose means are the
    // independent units of the variance: at least two groups.
    if (self && rendersChannelsInOnePass(s) && s.channelSampling == ChannelSampling::Hero)
        spp = std::max(6u, (spp + 2) / 3 * 3);
    return spp;
}

}  // namespace

Measurement measurementOf(const Arguments& args, const Sensor& sensor) {
    Measurement m;
    m.referenceFile = args.value("--reference");
    const bool self = args.has("--self-variance");
    if (!m.referenceFile && !self)
        throw UsageError("bench needs --reference REF.exr (make one with --make-reference) or --self-variance");
    if (m.referenceFile && self) throw UsageError("bench takes --reference or --self-variance, not both");
    if (m.referenceFile) {
        m.reference = readExr(*m.referenceFile);
        const RadianceImage& ref = m.reference;
        if (ref.width != sensor.imageWidth() || ref.height != sensor.imageHeight())
            throw InputError(*m.referenceFile, "reference image size does not match the scene's sensor");
        size_t refN = 0;
        for (size_t i = 0; i < ref.mean.size(); ++i)
            if (ref.coverage[i] > 0)
                for (int c = 0; c < 3; ++c, ++refN)
                    m.referenceVariance += double(ref.standardError[i][c]) * ref.standardError[i][c];
        m.referenceVariance /= double(std::max<size_t>(refN, 1));
    }
    for (const std::string& b : splitList(args.value("--budgets").value_or("1,2,4,8"))) {
        try {
            m.budgets_s.push_back(std::stod(b));
        } catch (const std::exception&) {
            throw UsageError("--budgets takes seconds, e.g. 1,2,4,8");
        }
        if (!(m.budgets_s.back() > 0)) throw UsageError("--budgets must be positive");
    }
    if (auto t = args.value("--target-relative-error")) {
        try {
            m.target = std::stod(*t);
        } catch (const std::exception&) {
            m.target = 0;
        }
        if (!(m.target > 0 && m.target < 1)) throw UsageError("--target-relative-error must be in (0, 1), e.g. 0.02");
    }
    return m;
}

Measured measure(const Scene& scene, const Sensor& sensor, const ChosenConfigurations& chosen, const Measurement& m,
                 const Arguments& args, int cores, bool acrossRanks, bool speaks) {
    const uint32_t selfSpp = uint32_t(args.integer("--spp", 2, 1 << 20).value_or(kMinSelfSpp));
    const bool self = m.self();
    Measured out;
    for (const std::string& name : chosen.names) {
        RenderSettings s = chosen.settings.at(name);
        s.spp = 1;
        s.seed = 1;
        const bool fixedSpp = self && args.has("--spp");
        double perSpp = fixedSpp ? 1.0 : render(scene, sensor, s, acrossRanks).seconds;  // calibration
        for (double budget : m.budgets_s) {
            if (fixedSpp && budget != m.budgets_s.front()) break;  // one render: the spp is fixed
            s.spp = samplesFor(s, budget, perSpp, args, self, selfSpp, acrossRanks);
            s.seed += 1;
            RenderResult r = render(scene, sensor, s, acrossRanks);
            if (!speaks) continue;
            // (With several renders the relative MSE is redone by poolRelativeMse, over one denominator.)
            const RenderError e = self ? selfVarianceError(r.film, ownMeanSquares(r.film))
                                       : errorAgainstReference(r.film, sensor, m.reference.mean);
            const bool camera = dynamic_cast<const CameraSensor*>(&sensor) != nullptr;
            const double medianRel = medianRelativeError(r.film, sensor, self ? nullptr : &m.reference, camera);
            std::optional<SurfaceColourError> colour;
            RGB bias{0, 0, 0};
            double withinTwoErrors = 0;
            const auto* surface = dynamic_cast<const SurfaceVoxelSensor*>(&sensor);
            if (!self && surface) {
                const SurfaceReflectances sr = surfaceReflectances(r.film, *surface, m.reference.mean,
                                                                   m.reference.standardError, scene.environment);
                colour = surfaceColourError(sr.points_mm, sr.film, sr.reference);
                withinTwoErrors = sr.withinTwoErrors;
                bias = sr.meanBias;
                // The last budget's per-voxel error, where it fails (written with the tables).
                if (budget == m.budgets_s.back())
                    out.errorMaps.push_back({name, std::move(colour->perVoxel), sr.imageIndex});
                colour->perVoxel.clear();
            }
            if (self) out.selfFilms.push_back(std::move(r.film));
            out.rows.push_back({name, budget, r.seconds, s.spp, e.rmse, e.rmseAll, e.relMse,
                                mseTimesSeconds(e.rmseAll, r.seconds), r.passSeconds, medianRel,
                                capabilitiesOf(s).deterministic ? (medianRel <= m.target ? r.seconds : INFINITY)
                                                                : timeToTarget(r.seconds, medianRel, m.target),
                                double(r.stats.scatterEvents) / (r.seconds * cores), colour, bias, withinTwoErrors});
            std::fprintf(stderr, "bench: %-24s budget %6.2f s: %5u spp, %7.2f s, RMSE %.5f\n", name.c_str(), budget,
                         s.spp, r.seconds, e.rmseAll);
        }
    }
    return out;
}

void poolRelativeMse(Measured& measured) {
    std::vector<BenchRow>& rows = measured.rows;
    const std::vector<Film>& films = measured.selfFilms;
    if (films.size() < 2) return;
    std::vector<double> rmse;
    for (size_t i = 0; i < films.size(); ++i) rmse.push_back(rows[i].rmse);
    const MeanSquares pooled = pooledMeanSquares(films, rmse);
    for (size_t i = 0; i < films.size(); ++i) rows[i].relMse = selfVarianceError(films[i], pooled).relMse;
}

}  // namespace pl
