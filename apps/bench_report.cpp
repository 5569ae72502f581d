#include "apps/bench_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "apps/number_text.h"
#include "io/output_file.h"
#include "runtime/distributed.h"

namespace pl {

namespace {

// Where a channel's own pass shows where the time and the error go: each
// channel's pass time and its equal-error speed-up over the baseline's pass
// (the set-up before the passes is in neither). Empty without separate passes.
std::string perChannelTable(const std::vector<BenchRow>& rows, const std::string& baseline,
                            const std::map<double, const BenchRow*>& baselineRows) {
    auto separate = [](const BenchRow& r) {
        return r.passSeconds[0] > 0 || r.passSeconds[1] > 0 || r.passSeconds[2] > 0;
    };
    if (std::none_of(rows.begin(), rows.end(), separate)) return "";
    // Zero where the row has no pass of its own (one-pass configurations).
    auto mseTime = [](const BenchRow& r, int c) {
        return double(r.rmseChannel[c]) * r.rmseChannel[c] * r.passSeconds[c];
    };
    std::ostringstream md;
    md << "\nPer channel (separate passes): each channel's pass time and its speed-up by the channel's MSE x pass "
          "time over "
       << baseline << "'s.\n\n";
    md << "| config | budget (s) | time R (s) | time G (s) | time B (s) | speed-up R | speed-up G | speed-up B |\n";
    md << "|---|---|---|---|---|---|---|---|\n";
    for (const BenchRow& r : rows) {
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

// CIEDE2000 against the reference on the surface sensor; empty without.
std::string colourTable(const std::vector<BenchRow>& rows) {
    if (std::none_of(rows.begin(), rows.end(), [](const BenchRow& r) { return r.colour.has_value(); })) return "";
    std::ostringstream md;
    char sigma[32];
    std::snprintf(sigma, sizeof sigma, "%g", kEyeFootprint_mm);
    md << "\nColour against the reference (reflectance, CIEDE2000 per surface voxel; filtered: both averaged over a "
       << sigma << " mm Gaussian on the surface, the eye's footprint):\n\n"
       << "| config | budget (s) | time (s) | mean | 95th pct | mean filtered | 95th pct filtered | reflectance bias R | G | B | within 2 errors |\n"
       << "|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const BenchRow& r : rows) {
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
std::string svgPlot(const std::vector<BenchRow>& rows, const std::string& title) {
    double tMin = 1e30, tMax = 0, eMin = 1e30, eMax = 0;
    for (const BenchRow& r : rows) {
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
    for (const BenchRow& r : rows)
        if (std::find(names.begin(), names.end(), r.config) == names.end()) names.push_back(r.config);
    for (size_t k = 0; k < names.size(); ++k) {
        const char* col = colors[k % 8];
        s << "<polyline fill='none' stroke='" << col << "' stroke-width='2' points='";
        for (const BenchRow& r : rows)
            if (r.config == names[k] && r.seconds > 0 && r.rmse > 0) s << x(r.seconds) << "," << y(r.rmse) << " ";
        s << "'/>\n";
        for (const BenchRow& r : rows)
            if (r.config == names[k] && r.seconds > 0 && r.rmse > 0) s << "<circle cx='" << x(r.seconds) << "' cy='" << y(r.rmse) << "' r='3' fill='" << col << "'/>\n";
        s << "<text x='" << W - R + 10 << "' y='" << T + 16 * (k + 1) << "' fill='" << col << "'>" << names[k] << "</text>\n";
    }
    s << "</svg>\n";
    return s.str();
}

// The per-voxel CIEDE2000 on the atlas (deltaEColour's scale).
RadianceImage deltaEImage(const VoxelErrorMap& map, int width, int height) {
    RadianceImage im;
    im.width = width;
    im.height = height;
    im.mean.assign(size_t(width) * height, RGB{0, 0, 0});
    im.standardError.assign(im.mean.size(), RGB{0, 0, 0});
    im.coverage.assign(im.mean.size(), 0.0f);
    for (size_t k = 0; k < map.deltaE.size(); ++k) {
        im.mean[size_t(map.imageIndex[k])] = deltaEColour(map.deltaE[k]);
        im.coverage[size_t(map.imageIndex[k])] = 1;
    }
    return im;
}

}  // namespace

void writeBenchTables(const Measured& measured, const Measurement& m, const std::vector<std::string>& names,
                      const SceneDescription& desc, const LimitWalkRate& limit, int threads, bool acrossRanks,
                      const std::string& prefix) {
    const std::vector<BenchRow>& rows = measured.rows;
    const std::string baseline =
        std::find(names.begin(), names.end(), "volpath") != names.end() ? "volpath" : names.front();
    std::map<double, const BenchRow*> baselineRows;  // per budget
    for (const BenchRow& r : rows)
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
    for (const BenchRow& r : rows) {
        double speedup = baselineRows.count(r.budget) ? baselineRows[r.budget]->mseTime / r.mseTime : NAN;
        char line[512];
        std::snprintf(line, sizeof line,
                      "%s | %.3g | %u | %.3f | %.5f | %.5f | %.5f | %.5f | %.4g | %.4g | %.2f | %.4g | %.4g | %.4g | %.3f",
                      r.config.c_str(), r.budget, r.spp, r.seconds, r.rmseChannel[0], r.rmseChannel[1],
                      r.rmseChannel[2], r.rmse, r.relMse, r.mseTime, speedup, r.medianRelativeError,
                      r.secondsToTarget, r.eventsPerSecondPerCore,
                      r.eventsPerSecondPerCore / limit.eventsPerSecondPerCore);
        md << "| " << line << " |\n";
        // The CSV row is the markdown row without bars and spaces.
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
    for (const VoxelErrorMap& map : measured.errorMaps)
        writePng(deltaEImage(map, m.reference.width, m.reference.height), prefix + "_" + map.config + "_deltaE.png");
    std::fputs(md.str().c_str(), stdout);
}

}  // namespace pl
