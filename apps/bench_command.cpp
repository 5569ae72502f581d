// printlight bench: error against run time (docs/performance.md).
//   printlight bench SCENE.json --make-reference REF.exr [--spp N] [--integrator I]
//   printlight bench SCENE.json --reference REF.exr [--budgets 1,2,4,8] [--configs a,b,...] [--out PREFIX]
//   printlight bench SCENE.json --self-variance [--budgets ...|--spp N] [--configs ...] [--out PREFIX]
//   (both: [--target-relative-error 0.02], the whole-object quality the
//   "time to" column extrapolates to: medianRelativeError, timeToTarget)
// Each configuration renders at each time budget (seconds; the spp is chosen
// from a 1-spp calibration run) and is compared with the reference: RMSE and
// relative MSE over all pixels and channels, MSE x time (lower is better),
// and the equal-error speed-up over volpath (or, without a volpath
// configuration, over the first one) = (MSE x time)_volpath / (MSE x time)_config. Writes PREFIX.md, PREFIX.csv and PREFIX.svg.
// --self-variance needs no reference: the expected MSE of an unbiased
// estimator is its variance, estimated per pixel from the samples
// themselves (stderr^2, at least kMinSelfSpp samples; with hero channels,
// which go round groups of three samples, at least two groups). Cheap for large scenes;
// it cannot see bias (the tests and the reference mode do) and it
// underestimates heavy-tailed estimators at few samples. Its relative MSE
// divides each pixel's variance by one squared mean for all renders of the
// run (their means pooled, weighted by 1 / MSE), not by each render's own.
//   printlight bench --limit [--threads N]: the limit walk's rate alone
//   (apps/limit_walk.h). Every bench run measures it too, and the tables give
//   each render's scattering events per second per core against it.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "apps/arguments.h"
#include "apps/bench_error_check.h"
#include "apps/bench_loop.h"
#include "apps/command_options.h"
#include "runtime/distributed.h"
#include "apps/limit_walk.h"
#include "apps/number_text.h"
#include "runtime/progress.h"
#include "integrators/printpt/half_space_walk.h"
#include "render/registry.h"
#include "compare/surface_colour_error.h"
#include "io/image_io.h"
#include "core/input_error.h"
#include "io/output_file.h"
#include "render/progressive_render.h"
#include "render/scene_io.h"

namespace pl {

namespace {

// Named configurations: every registered estimator by its name, with its
// defaults, and these variants of them, each an estimator and its
// overrides (parseConfiguration).
const std::vector<std::pair<const char*, const char*>> kVariants = {
    // Every flight starts with a boundary query (no clearance first).
    {"volpath-geometry-first", "volpath/clearance_first=0"},
    // The thesis' Russian roulette: survival min(0.99, throughput) at every collision.
    {"printpt-brecka", "printpt/rr_cap=0.99/rr_threshold=1/rr_threshold_absorbing=1"},
    {"printpt-analog", "printpt/rr_threshold=1/rr_threshold_absorbing=1"},
    {"printpt-k1", "printpt/branches=1"},
    {"printpt-k16", "printpt/branches=16"},
    {"printpt-geometry-first", "printpt/medium_first=0"},
    {"printpt-no-clearance", "printpt/clearance=0"},
    {"printpt-no-balls", "printpt/ball_walks=0"},
    {"printpt-random-fresnel", "printpt/fresnel_weighting=0"},
    {"printpt-nee", "printpt/nee=1"},
    // Light tracing (the sensor must have the patch footprint): the light
    // side scoring into every pixel (no hybrid), scoring at collisions,
    // along tracks at other spacings, more particles per block.
    {"lighttrace-no-hybrid", "lighttrace/lighttrace_hybrid=0"},
    {"lighttrace-collisions", "lighttrace/lighttrace_scoring=collisions"},
    {"lighttrace-tracks-0.5", "lighttrace/lighttrace_track_spacing_mfp=0.5"},
    {"lighttrace-tracks-2", "lighttrace/lighttrace_track_spacing_mfp=2"},
    {"lighttrace-p4", "lighttrace/particles_per_pixel=4"},
    {"lighttrace-p16", "lighttrace/particles_per_pixel=16"},
    // The textbook tracker: one majorant for the whole grid instead of one per brick.
    {"volpath-global-majorant", "volpath/majorants=global"},
    {"printpt-global-majorant", "printpt/majorants=global"},
    // Three channels: one pass per channel, or one path for all three.
    {"volpath-separate", "volpath/channel_sampling=separate"},
    {"volpath-hero", "volpath/channel_sampling=hero"},
    {"volpath-spectral", "volpath/channel_sampling=spectral"},
    {"printpt-separate", "printpt/channel_sampling=separate"},
    {"printpt-hero", "printpt/channel_sampling=hero"},
    {"printpt-spectral", "printpt/channel_sampling=spectral"},
};

// One override of a configuration: a render-block name (majorants,
// channel_sampling) or a key of the estimator's own, as the scene file
// spells it ("k" is printpt's branches).
void applyOverride(RenderSettings& s, std::string key, const std::string& value) {
    if (key == "k") key = "branches";
    if (key == "majorants" || key == "channel_sampling") {
        const bool known = key == "majorants" ? parseEnum(kMajorantsNames, value).has_value()
                                              : parseEnum(kChannelSamplingNames, value).has_value();
        if (!known)
            throw std::invalid_argument(key + ": must be " + (key == "majorants" ? enumNames(kMajorantsNames)
                                                                                  : enumNames(kChannelSamplingNames)));
        if (key == "majorants") s.majorants = *parseEnum(kMajorantsNames, value);
        else s.channelSampling = *parseEnum(kChannelSamplingNames, value);
        return;
    }
    const ParameterInfo* info = findParameter(integratorKindOf(s).factory.parameters(), key);
    if (info && info->isText()) {
        s.parameters.setText(key, value);
        return;
    }
    try {
        s.parameters.set(key, value == "true" ? 1.0 : value == "false" ? 0.0 : std::stod(value));
    } catch (const std::exception&) {
        throw std::invalid_argument(key + ": needs a number");
    }
}

// A configuration: a name (an estimator's or a variant's) and overrides
// after slashes, e.g. "printpt/k=1/rr_threshold=0.2/nee=1",
// "lighttrace/particles_per_pixel=2", "pb2d/beams_radius_voxels=4",
// "printpt-hero/majorants=global"; nullopt for an unknown name. Each
// starts from the scene's settings with the estimator's defaults.
std::optional<RenderSettings> parseConfiguration(const std::string& spec, const RenderSettings& base) {
    std::vector<std::string> parts = splitList(spec, '/');
    if (parts.empty()) return std::nullopt;
    for (const auto& [name, variant] : kVariants)
        if (parts[0] == name) {
            std::vector<std::string> own = splitList(variant, '/');
            parts.erase(parts.begin());
            parts.insert(parts.begin(), own.begin(), own.end());
            break;
        }
    if (!findIntegratorKind(parts[0])) return std::nullopt;
    RenderSettings s = base;
    s.integrator = parts[0];
    s.reentry = false;
    s.parameters = EstimatorParameters{};
    s.parameters.materialsFile = base.parameters.materialsFile;
    for (size_t i = 1; i < parts.size(); ++i) {
        const size_t eq = parts[i].find('=');
        if (eq == std::string::npos) throw UsageError("configuration '" + spec + "': overrides are key=value");
        try {
            applyOverride(s, parts[i].substr(0, eq), parts[i].substr(eq + 1));
        } catch (const std::invalid_argument& e) {
            throw UsageError("configuration '" + spec + "': " + e.what());
        }
    }
    const IntegratorKind& kind = integratorKindOf(s);
    if (auto problem = checkParameters(kind.factory.parameters(), s.parameters, kind.name))
        throw UsageError("configuration '" + spec + "': " + problem->key + ": " + problem->what);
    return s;
}

// The names bench knows: the estimators' and the variants'.
std::vector<std::string> configurationNames() {
    std::vector<std::string> names;
    for (const IntegratorKind& k : integratorKinds()) names.push_back(k.name);
    for (const auto& v : kVariants) names.push_back(v.first);
    return names;
}

struct Row {
    std::string config;
    double budget, seconds;
    uint32_t spp;
    RGB rmseChannel;
    double rmse, relMse, mseTime;
    RGB passSeconds;  // per channel (separate passes; zero for one pass)
    double medianRelativeError = 0, secondsToTarget = 0;  // whole-object quality (timeToTarget)
    double eventsPerSecondPerCore = 0;  // scattering events over wall time and threads
    // Against a reference on the surface-voxel sensor: CIEDE2000 of the
    // reflectance (compare/surface_colour_error.h); none otherwise.
    std::optional<SurfaceColourError> colour;
    RGB reflectanceBias{0, 0, 0};  // mean of (render - reference) reflectance over the surface voxels
    // The share of voxel channels whose difference from the reference is
    // within twice the two standard errors combined (reported errors that
    // cover every source of error put about 95 % there).
    double withinTwoErrors = 0;
};

// Where a channel's own pass shows where the time and the error go: each
// channel's pass time and its equal-error speed-up over the baseline's pass
// (the set-up before the passes is in neither). Empty without separate passes.
std::string perChannelTable(const std::vector<Row>& rows, const std::string& baseline,
                            const std::map<double, const Row*>& baselineRows) {
    auto separate = [](const Row& r) { return r.passSeconds[0] > 0 || r.passSeconds[1] > 0 || r.passSeconds[2] > 0; };
    if (std::none_of(rows.begin(), rows.end(), separate)) return "";
    // Zero where the row has no pass of its own (one-pass configurations).
    auto mseTime = [](const Row& r, int c) { return double(r.rmseChannel[c]) * r.rmseChannel[c] * r.passSeconds[c]; };
    std::ostringstream md;
    md << "\nPer channel (separate passes): each channel's pass time and its speed-up by the channel's MSE x pass "
          "time over "
       << baseline << "'s.\n\n";
    md << "| config | budget (s) | time R (s) | time G (s) | time B (s) | speed-up R | speed-up G | speed-up B |\n";
    md << "|---|---|---|---|---|---|---|---|\n";
    for (const Row& r : rows) {
        if (!separate(r)) continue;
        char line[256];
        std::snprintf(line, sizeof line, "%s | %.3g | %.3f | %.3f | %.3f", r.config.c_str(), r.budget,
                      r.passSeconds[0], r.passSeconds[1], r.passSeconds[2]);
        md << "| " << line;
        const auto b = baselineRows.find(r.budget);
        for (int c = 0; c < 3; ++c) {
            char cell[32] = "-";
            if (b != baselineRows.end() && mseTime(r, c) > 0 && mseTime(*b->second, c) > 0)
                std::snprintf(cell, sizeof cell, "%.2f", mseTime(*b->second, c) / mseTime(r, c));
            md << " | " << cell;
        }
        md << " |\n";
    }
    return md.str();
}

struct Errors {
    RGB rmse;
    double rmseAll, relMse;
};

constexpr uint32_t kMinSelfSpp = 4;

// The film's own variance estimate as the expected squared error: per
// pixel the samples' spread (unbiased, so its sum over pixels is too,
// where a pixel's own may miss rare events; the per-pixel standard error,
// Film::standardError, is conservative there) and what samples share
// through printpt's estimated control means. The relative MSE
// divides by relativeTo(p, c), a squared mean: with the film's own means,
// whose noise differs from one configuration to the next, dark pixels
// weigh in by how noisy each render's estimate of their darkness is, and a
// noisier configuration can come out ahead.
template <class RelativeTo>
Errors selfVariance(const Film& film, RelativeTo&& relativeTo) {
    double se[3] = {0, 0, 0}, rel = 0;
    size_t n = film.pixelCount();
    for (size_t p = 0; p < n; ++p)
        for (int c = 0; c < 3; ++c) {
            double mSq = relativeTo(p, c), v = std::pow(double(film.spreadError(p, c)), 2) +
                                               std::pow(double(film.sharedError(p, c)), 2);
            se[c] += v;
            rel += v / (mSq + 1e-3);
        }
    Errors e;
    for (int c = 0; c < 3; ++c) e.rmse[c] = float(std::sqrt(se[c] / double(n)));
    e.rmseAll = std::sqrt((se[0] + se[1] + se[2]) / (3.0 * n));
    e.relMse = rel / (3.0 * n);
    return e;
}

// The time to bring that median down to the target, from a render that
// took `seconds`: error falls as 1 / sqrt(time) for these estimators (an
// extrapolation where the render did not reach it; the render's own time
// where it did).
double timeToTarget(double seconds, double medianRelativeError, double target) {
    return medianRelativeError <= target ? seconds : seconds * std::pow(medianRelativeError / target, 2);
}

Errors compare(const Film& film, const Sensor& sensor, const RadianceImage& ref) {
    double se[3] = {0, 0, 0}, rel = 0;
    size_t n = 0;
    for (size_t p = 0; p < film.pixelCount(); ++p) {
        int64_t i = sensor.pixelImageIndex(p);
        if (i < 0) continue;  // hidden in the atlas: not in the reference image
        ++n;
        for (int c = 0; c < 3; ++c) {
            double r = ref.mean[size_t(i)][c], d = film.mean(p, c) - r;
            se[c] += d * d;
            rel += d * d / (r * r + 1e-3);
        }
    }
    Errors e;
    for (int c = 0; c < 3; ++c) e.rmse[c] = float(std::sqrt(se[c] / double(n)));
    e.rmseAll = std::sqrt((se[0] + se[1] + se[2]) / (3.0 * n));
    e.relMse = rel / (3.0 * n);
    return e;
}

// The reflectance (radiance over the surroundings' radiance) of every
// surface voxel the atlas shows, from the film and from the reference,
// with the voxels' surface points.
struct SurfaceReflectances {
    std::vector<Point3f> points_mm;
    std::vector<RGB> film, reference;
    std::vector<int64_t> imageIndex;
    RGB meanBias{0, 0, 0};  // of film - reference
    double withinTwoErrors = 0;
};
SurfaceReflectances surfaceReflectances(const Film& film, const SurfaceVoxelSensor& sensor, const RadianceImage& ref,
                                        const RGB& environment) {
    SurfaceReflectances s;
    for (size_t p = 0; p < film.pixelCount(); ++p) {
        const int64_t i = sensor.pixelImageIndex(p);
        if (i < 0) continue;
        s.points_mm.push_back(sensor.pixels()[p].surfacePoint_mm);
        RGB f, r;
        for (int c = 0; c < 3; ++c) {
            f[c] = film.mean(p, c) / environment[c];
            r[c] = ref.mean[size_t(i)][c] / environment[c];
        }
        s.film.push_back(f);
        s.reference.push_back(r);
        s.imageIndex.push_back(i);
        for (int c = 0; c < 3; ++c) {
            const double e = std::hypot(double(film.standardError(p, c)), double(ref.standardError[size_t(i)][c]));
            if (std::abs(double(film.mean(p, c)) - ref.mean[size_t(i)][c]) <= 2.0 * e) s.withinTwoErrors += 1;
        }
    }
    for (size_t k = 0; k < s.film.size(); ++k)
        for (int c = 0; c < 3; ++c) s.meanBias[c] += (s.film[k][c] - s.reference[k][c]) / float(s.film.size());
    if (!s.film.empty()) s.withinTwoErrors /= 3.0 * double(s.film.size());
    return s;
}

// The per-voxel CIEDE2000 on the atlas (deltaEColour's scale).
RadianceImage deltaEImage(const std::vector<float>& deltaE, const std::vector<int64_t>& imageIndex, int width,
                          int height) {
    RadianceImage im;
    im.width = width;
    im.height = height;
    im.mean.assign(size_t(width) * height, RGB{0, 0, 0});
    im.standardError.assign(im.mean.size(), RGB{0, 0, 0});
    im.coverage.assign(im.mean.size(), 0.0f);
    for (size_t k = 0; k < deltaE.size(); ++k) {
        im.mean[size_t(imageIndex[k])] = deltaEColour(deltaE[k]);
        im.coverage[size_t(imageIndex[k])] = 1;
    }
    return im;
}

std::string colourTable(const std::vector<Row>& rows) {
    if (std::none_of(rows.begin(), rows.end(), [](const Row& r) { return r.colour.has_value(); })) return "";
    std::ostringstream md;
    char sigma[32];
    std::snprintf(sigma, sizeof sigma, "%g", kEyeFootprint_mm);
    md << "\nColour against the reference (reflectance, CIEDE2000 per surface voxel; filtered: both averaged over a "
       << sigma << " mm Gaussian on the surface, the eye's footprint):\n\n"
       << "| config | budget (s) | time (s) | mean | 95th pct | mean filtered | 95th pct filtered | reflectance bias R | G | B | within 2 errors |\n"
       << "|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Row& r : rows) {
        if (!r.colour) continue;
        char line[256];
        std::snprintf(line, sizeof line, "| %s | %.3g | %.3f | %.2f | %.2f | %.2f | %.2f | %+.4f | %+.4f | %+.4f | %.1f %% |\n",
                      r.config.c_str(), r.budget, r.seconds, r.colour->mean, r.colour->p95, r.colour->meanFiltered,
                      r.colour->p95Filtered, r.reflectanceBias[0], r.reflectanceBias[1], r.reflectanceBias[2],
                      100.0 * r.withinTwoErrors);
        md << line;
    }
    return md.str();
}

// Log-log plot of RMSE against time, one polyline per configuration.
std::string svgPlot(const std::vector<Row>& rows, const std::string& title) {
    double tMin = 1e30, tMax = 0, eMin = 1e30, eMax = 0;
    for (const Row& r : rows) {
        if (!(r.seconds > 0 && r.rmse > 0)) continue;  // not on a log scale
        tMin = std::min(tMin, r.seconds); tMax = std::max(tMax, r.seconds);
        eMin = std::min(eMin, r.rmse); eMax = std::max(eMax, r.rmse);
    }
    if (tMax == 0 || eMax == 0) tMin = tMax = eMin = eMax = 1;  // nothing to plot: empty axes
    double lt0 = std::floor(std::log10(tMin)), lt1 = std::ceil(std::log10(tMax));
    double le0 = std::floor(std::log10(eMin)), le1 = std::ceil(std::log10(eMax));
    if (lt1 <= lt0) lt1 = lt0 + 1;
    if (le1 <= le0) le1 = le0 + 1;
    const double W = 640, H = 420, L = 70, R = 190, T = 40, B = 50;
    auto x = [&](double t) { return L + (std::log10(t) - lt0) / (lt1 - lt0) * (W - L - R); };
    auto y = [&](double e) { return H - B - (std::log10(e) - le0) / (le1 - le0) * (H - T - B); };
    std::ostringstream s;
    s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='" << H << "' font-family='sans-serif' font-size='12'>\n";
    s << "<rect width='100%' height='100%' fill='white'/>\n<text x='" << L << "' y='20'>" << title << "</text>\n";
    s << "<rect x='" << L << "' y='" << T << "' width='" << W - L - R << "' height='" << H - T - B << "' fill='none' stroke='black'/>\n";
    for (double d = lt0; d <= lt1; d += 1)
        s << "<text x='" << x(std::pow(10, d)) - 10 << "' y='" << H - B + 16 << "'>1e" << d << "</text>\n";
    for (double d = le0; d <= le1; d += 1)
        s << "<text x='" << 20 << "' y='" << y(std::pow(10, d)) + 4 << "'>1e" << d << "</text>\n";
    s << "<text x='" << (W - R + L) / 2 - 30 << "' y='" << H - 12 << "'>time (s)</text>\n";
    s << "<text x='14' y='" << T - 8 << "'>RMSE</text>\n";
    const char* colors[] = {"#000000", "#d62728", "#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2"};
    std::vector<std::string> names;
    for (const Row& r : rows)
        if (std::find(names.begin(), names.end(), r.config) == names.end()) names.push_back(r.config);
    for (size_t k = 0; k < names.size(); ++k) {
        const char* col = colors[k % 8];
        s << "<polyline fill='none' stroke='" << col << "' stroke-width='2' points='";
        for (const Row& r : rows)
            if (r.config == names[k] && r.seconds > 0 && r.rmse > 0) s << x(r.seconds) << "," << y(r.rmse) << " ";
        s << "'/>\n";
        for (const Row& r : rows)
            if (r.config == names[k] && r.seconds > 0 && r.rmse > 0) s << "<circle cx='" << x(r.seconds) << "' cy='" << y(r.rmse) << "' r='3' fill='" << col << "'/>\n";
        s << "<text x='" << W - R + 10 << "' y='" << T + 16 * (k + 1) << "' fill='" << col << "'>" << names[k] << "</text>\n";
    }
    s << "</svg>\n";
    return s.str();
}

// The configurations --configs names, and what the scene must load for them.
struct ChosenConfigurations {
    std::vector<std::string> names;
    std::map<std::string, RenderSettings> settings;
    SceneNeeds needs;
};

ChosenConfigurations chooseConfigurations(const Arguments& args, const RenderSettings& base) {
    ChosenConfigurations chosen;
    chosen.names = splitList(args.value("--configs").value_or("volpath,printpt"));
    for (const std::string& n : chosen.names) {
        auto s = parseConfiguration(n, base);
        if (!s) {
            std::string known;
            for (const std::string& k : configurationNames()) known += " " + k;
            throw UsageError("unknown configuration '" + n + "'; known:" + known + " (each takes /key=value overrides)");
        }
        chosen.settings[n] = *s;
        chosen.needs |= sceneNeedsOf(*s);
    }
    return chosen;
}

// --make-reference: many samples of the trusted estimator, with their own
// RMS standard error.
void makeReference(const Scene& scene, const Sensor& sensor, RenderSettings s, const std::string& file,
                   const Arguments& args, const SceneDescription& desc, bool acrossRanks, bool speaks) {
    s.spp = uint32_t(args.integer("--spp", 1, 1 << 24).value_or(256));
    s.seed = 0x5eed;
    s.showProgress = speaks && ProgressBar::stderrIsTerminal();
    refuseToOverwriteInputs(file, desc.inputFiles());
    RenderResult r = render(scene, sensor, s, acrossRanks);
    if (!speaks) return;
    RadianceImage im = filmToImage(r.film, sensor);
    im.metadata = {{"reference_spp", std::to_string(s.spp)}, {"integrator", s.integrator}};
    writeExr(im, file);
    double var = 0;
    size_t n = 0;
    for (size_t p = 0; p < r.film.pixelCount(); ++p)
        for (int c = 0; c < 3; ++c, ++n) var += double(r.film.standardError(p, c)) * r.film.standardError(p, c);
    std::printf("reference %s: %s, %u spp, %.1f s; its own RMS standard error per pixel %.3g\n", file.c_str(),
                s.integrator.c_str(), s.spp, r.seconds, std::sqrt(var / double(n)));
}

// --error-check: whether the reported errors are honest at these spp.
void checkErrors(const Scene& scene, const Sensor& sensor, const ChosenConfigurations& chosen,
                 const std::string& spps, const Arguments& args, bool acrossRanks, bool speaks) {
    std::vector<uint32_t> counts;
    for (const std::string& n : splitList(spps)) {
        long v = 0;
        try {
            v = std::stol(n);
        } catch (const std::exception&) {
        }
        if (v < 1 || v > long(RenderSettings::kMostSpp)) throw UsageError("--error-check takes sample counts, e.g. 1,2,8");
        counts.push_back(uint32_t(v));
    }
    std::vector<std::pair<std::string, RenderSettings>> configs;
    for (const std::string& n : chosen.names) configs.emplace_back(n, chosen.settings.at(n));
    const uint64_t seed = uint64_t(args.integer("--seed", 0, INT64_MAX - 1).value_or(11));
    const std::string md = errorCheckTable(scene, sensor, configs, counts, seed, acrossRanks);
    if (!speaks) return;
    writeTextFile(args.value("--out").value_or("bench") + ".md", md);
    std::fputs(md.c_str(), stdout);
}

// What the errors are measured against and at which budgets.
struct Measurement {
    std::optional<std::string> referenceFile;  // none: self-variance
    RadianceImage reference;
    double referenceVariance = 0;  // its mean squared standard error per pixel channel
    std::vector<double> budgets_s;  // each render's time budget
    double target = 0.02;          // the whole-object median relative error (timeToTarget)
    bool self() const { return !referenceFile; }
};

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

// Every configuration at every budget: a row each (on rank 0), and with
// self-variance each render's film, kept until all are done for the
// relative MSE (one denominator for all renders); per configuration, its
// per-voxel CIEDE2000 on the atlas (surface sensor, reference).
struct Measured {
    std::vector<Row> rows;
    std::vector<Film> selfFilms;
    std::vector<std::pair<std::string, RadianceImage>> errorMaps;
};

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

Measured measure(const Scene& scene, const Sensor& sensor, const ChosenConfigurations& chosen, const Measurement& m,
                 const Arguments& args, int cores, bool acrossRanks, bool speaks) {
    // Self-variance: at least kMinSelfSpp samples, or exactly --spp (>= 2:
    // the sample variance is unbiased from two samples on).
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
            // (With several renders the relative MSE is redone below, over one denominator.)
            auto ownMeanSq = [&](size_t p, int c) { return double(r.film.mean(p, c)) * r.film.mean(p, c); };
            Errors e = self ? selfVariance(r.film, ownMeanSq) : compare(r.film, sensor, m.reference);
            const bool camera = dynamic_cast<const CameraSensor*>(&sensor) != nullptr;
            const double medianRel = medianRelativeError(r.film, sensor, self ? nullptr : &m.reference, camera);
            std::optional<SurfaceColourError> colour;
            RGB bias{0, 0, 0};
            double withinTwoErrors = 0;
            const auto* surface = dynamic_cast<const SurfaceVoxelSensor*>(&sensor);
            if (!self && surface) {
                const SurfaceReflectances sr = surfaceReflectances(r.film, *surface, m.reference, scene.environment);
                colour = surfaceColourError(sr.points_mm, sr.film, sr.reference);
                withinTwoErrors = sr.withinTwoErrors;
                bias = sr.meanBias;
                // The last budget's per-voxel error, where it fails (written with the tables).
                if (budget == m.budgets_s.back())
                    out.errorMaps.emplace_back(
                        name, deltaEImage(colour->perVoxel, sr.imageIndex, m.reference.width, m.reference.height));
                colour->perVoxel.clear();
            }
            if (self) out.selfFilms.push_back(std::move(r.film));
            out.rows.push_back({name, budget, r.seconds, s.spp, e.rmse, e.rmseAll, e.relMse,
                                e.rmseAll * e.rmseAll * r.seconds, r.passSeconds, medianRel,
                                capabilitiesOf(s).deterministic ? (medianRel <= m.target ? r.seconds : INFINITY)
                                                                : timeToTarget(r.seconds, medianRel, m.target),
                                double(r.stats.scatterEvents) / (r.seconds * cores), colour, bias, withinTwoErrors});
            std::fprintf(stderr, "bench: %-24s budget %6.2f s: %5u spp, %7.2f s, RMSE %.5f\n", name.c_str(), budget,
                         s.spp, r.seconds, e.rmseAll);
        }
    }
    return out;
}

// Self-variance over several renders: one denominator for every render,
// the renders' means pooled with weights 1 / (render's MSE), so the
// comparison between configurations is like for like and the least noisy
// render counts most.
void poolRelativeMse(Measured& measured) {
    std::vector<Row>& rows = measured.rows;
    const std::vector<Film>& films = measured.selfFilms;
    if (films.size() < 2) return;
    const size_t n = films.front().pixelCount();
    std::vector<std::array<double, 3>> pooled(n, {0, 0, 0});
    double weights = 0;
    for (size_t i = 0; i < films.size(); ++i) {
        const double w = 1.0 / std::max(rows[i].rmse * rows[i].rmse, 1e-30);
        weights += w;
        for (size_t p = 0; p < n; ++p)
            for (int c = 0; c < 3; ++c) pooled[p][c] += w * films[i].mean(p, c);
    }
    auto meanSq = [&](size_t p, int c) {
        const double m = pooled[p][c] / weights;
        return m * m;
    };
    for (size_t i = 0; i < films.size(); ++i) rows[i].relMse = selfVariance(films[i], meanSq).relMse;
}

// The tables (markdown and CSV), with the equal-error speed-up over the
// baseline (volpath, or else the first configuration) per budget (MSE x
// time ratio), the per-channel and colour tables and the plot.
void writeBenchTables(const Measured& measured, const Measurement& m, const std::vector<std::string>& names,
                      const SceneDescription& desc, const LimitWalkRate& limit, int threads, bool acrossRanks,
                      const std::string& prefix) {
    const std::vector<Row>& rows = measured.rows;
    const std::string baseline =
        std::find(names.begin(), names.end(), "volpath") != names.end() ? "volpath" : names.front();
    std::map<double, const Row*> baselineRows;  // per budget
    for (const Row& r : rows)
        if (r.config == baseline) baselineRows[r.budget] = &r;
    std::ostringstream md, csv;
    if (m.self())
        md << "Scene `" << desc.sceneFile.string() << "`, no reference: RMSE and relMSE are each render's own "
           << "variance estimate (stderr^2 per pixel, at least " << kMinSelfSpp << " spp); relMSE divides it by one squared "
           << "mean for all renders, their means pooled with weights 1/MSE (with one render: its own).\n\n";
    else
        md << "Scene `" << desc.sceneFile.string() << "`, reference `" << *m.referenceFile
           << "` (RMS standard error per pixel " << std::sqrt(m.referenceVariance) << ").\n\n";
    md << "Limit walk, same run: " << siRate(limit.eventsPerSecondPerCore) << " scattering events/s/core on "
       << limit.threads << " thread(s) (no lookups: exponential flights and HG sampling in an infinite medium). "
       << "events/s/core: each render's scattering events over its wall time and threads";
    if (acrossRanks) md << " (" << Distributed::ranks() << " MPI ranks of " << threads << " thread(s))";
    md << ".\n\n";
    char targetText[32];
    std::snprintf(targetText, sizeof targetText, "%g %%", 100.0 * m.target);
    md << "| config | budget (s) | spp | time (s) | RMSE R | RMSE G | RMSE B | RMSE | relMSE | MSE x time | speed-up vs "
       << baseline << " | median rel. error | time to " << targetText << " (s) | events/s/core | of limit |\n";
    md << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    csv << "config,budget_s,spp,time_s,rmse_r,rmse_g,rmse_b,rmse,rel_mse,mse_x_time,speedup_vs_baseline,"
           "median_rel_error,seconds_to_target,events_per_s_per_core,fraction_of_limit\n";
    for (const Row& r : rows) {
        double speedup = baselineRows.count(r.budget) ? baselineRows[r.budget]->mseTime / r.mseTime : NAN;
        char line[512];
        std::snprintf(line, sizeof line,
                      "%s | %.3g | %u | %.3f | %.5f | %.5f | %.5f | %.5f | %.4g | %.4g | %.2f | %.4g | %.4g | %.4g | %.3f",
                      r.config.c_str(), r.budget, r.spp, r.seconds, r.rmseChannel[0], r.rmseChannel[1],
                      r.rmseChannel[2], r.rmse, r.relMse, r.mseTime, speedup, r.medianRelativeError,
                      r.secondsToTarget, r.eventsPerSecondPerCore,
                      r.eventsPerSecondPerCore / limit.eventsPerSecondPerCore);
        md << "| " << line << " |\n";
        std::string c = line;
        for (char& ch : c)
            if (ch == '|') ch = ',';
        c.erase(std::remove(c.begin(), c.end(), ' '), c.end());
        csv << c << "\n";
    }
    md << perChannelTable(rows, baseline, baselineRows);
    md << colourTable(rows);
    writeTextFile(prefix + ".md", md.str());
    writeTextFile(prefix + ".csv", csv.str());
    writeTextFile(prefix + ".svg", svgPlot(rows, desc.sceneFile.filename().string() + ": RMSE against time"));
    for (const auto& [name, image] : measured.errorMaps) writePng(image, prefix + "_" + name + "_deltaE.png");
    std::fputs(md.str().c_str(), stdout);
}

}  // namespace

int benchCommand(const std::vector<std::string>& argv) {
    Arguments args("bench", argv,
                   {{"--make-reference", "REF.exr", "render a reference (with --spp, default 256, and --integrator)"},
                    {"--reference", "REF.exr", "the error of each configuration against a reference"},
                    {"--self-variance", "", "the error from each render's own variance (no reference)"},
                    {"--error-check", "1,2,8", "whether the reported errors are honest at these spp (two seeds each)"},
                    kSeedOption,
                    {"--budgets", "1,2,4,...", "time budgets in seconds: each configuration renders the samples that fit"},
                    {"--configs", "A,B,...", "estimator configurations (default volpath,printpt)"},
                    kSppOption,
                    integratorOption(),
                    {"--out", "PREFIX", "tables and plot: PREFIX.md, .csv, .svg (default bench)"},
                    {"--target-relative-error", "E", "the time to that median per-pixel relative error (default 0.02)"},
                    kThreadsOption,
                    {"--limit", "", "the limit walk (a lookup-free walk in an infinite medium) alone"},
                    {"--loop", "CHANGES",
                     "the optimisation loop's predictions on recorded label changes (optimize --record-changes): "
                     "noise over the footprint and seconds per iteration"},
                    {"--carry-over", "none,kept,control-variates", "with --loop: the ways of predicting (default all)"}});
    ThreadLimit threads(args);
    if (args.has("--limit") && args.positional().empty()) {
        const LimitWalkRate limit = measureLimitWalk(threads.count);
        std::printf("limit walk: %s scattering events/s/core (%s events on %d thread(s) in %.2f s)\n",
                    siRate(limit.eventsPerSecondPerCore).c_str(), withThousands(limit.events).c_str(), limit.threads,
                    limit.seconds);
        return 0;
    }
    if (args.positional().size() != 1) throw UsageError("bench needs exactly one SCENE.json (or --limit alone)");
    SceneDescription desc = parseScene(args.positional()[0]);
    if (auto file = args.value("--loop")) {
        const LabelChangeHistory changes = readLabelChanges(*file);
        std::vector<std::string> methods = splitList(args.value("--carry-over").value_or("none,kept,control-variates"));
        for (const std::string& m : methods)
            if (m != "none" && m != "kept" && m != "control-variates")
                throw UsageError("--carry-over takes none, kept and control-variates");
        RenderSettings loop = desc.render;
        loop.channels = {0, 1, 2};
        loop.reentry = false;
        loop.spp = uint32_t(args.integer("--spp", 1, RenderSettings::kMostSpp).value_or(2));
        if (auto name = args.value("--integrator")) chooseIntegrator(loop, *name, "--integrator");
        const std::string md = loopTable(desc, loop, changes, methods,
                                         uint64_t(args.integer("--seed", 0, INT64_MAX - 1).value_or(1)));
        const std::string out = args.value("--out").value_or("bench") + "_loop.md";
        refuseToOverwriteInputs(out, desc.inputFiles());
        writeTextFile(out, md);
        std::fputs(md.c_str(), stdout);
        return 0;
    }
    RenderSettings base = desc.render;
    base.channels = {0, 1, 2};
    base.reentry = false;  // surface prediction: the estimators must agree
    ChosenConfigurations chosen = chooseConfigurations(args, base);
    // The reference: many samples of the trusted estimator (volpath by default).
    RenderSettings reference = base;
    reference.integrator = args.value("--integrator").value_or("volpath");
    auto makeRefPath = args.value("--make-reference");
    if (makeRefPath) chosen.needs |= sceneNeedsOf(reference);
    Scene scene;
    std::unique_ptr<Sensor> sensor;
    runOnEveryRank([&] {  // on every rank, or none (rank 0 says why)
        scene = loadScene(desc, chosen.needs);
        sensor = makeSensor(desc, scene);
    });
    // Across MPI ranks every render is split over them (each renders its
    // share of the pixels); rank 0 measures, prints and writes. Times are
    // rank 0's wall times; events/s/core count every rank's threads.
    const bool acrossRanks = Distributed::ranks() > 1, speaks = Distributed::rank() == 0;
    const int cores = threads.count * Distributed::ranks();
    if (makeRefPath) {
        makeReference(scene, *sensor, reference, *makeRefPath, args, desc, acrossRanks, speaks);
        return 0;
    }
    if (auto spps = args.value("--error-check")) {
        checkErrors(scene, *sensor, chosen, *spps, args, acrossRanks, speaks);
        return 0;
    }
    const Measurement m = measurementOf(args, *sensor);
    // The floor every configuration's event rate is read against, in this
    // process and run.
    const LimitWalkRate limit = measureLimitWalk(threads.count);
    if (speaks) std::fprintf(stderr, "bench: limit walk %s events/s/core\n", siRate(limit.eventsPerSecondPerCore).c_str());
    Measured measured = measure(scene, *sensor, chosen, m, args, cores, acrossRanks, speaks);
    if (!speaks) return 0;
    poolRelativeMse(measured);
    writeBenchTables(measured, m, chosen.names, desc, limit, threads.count, acrossRanks,
                     args.value("--out").value_or("bench"));
    return 0;
}

}  // namespace pl
