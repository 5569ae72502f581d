// printlight batch: renders the scenes of a manifest, each with its own seed
// and sample count, and optionally compares every result with a stored one
// (regression renders). Results are EXRs in sensor-pixel order.

#include <chrono>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "apps/arguments.h"
#include "apps/command_options.h"
#include "apps/code_fingerprint.h"
#include "runtime/distributed.h"
#include "runtime/progress.h"
#include "compare/result_comparison.h"
#include "render/registry.h"
#include "render/batch_manifest.h"
#include "io/image_io.h"
#include "core/input_error.h"
#include "io/output_file.h"
#include "render/render_outputs.h"
#include "render/scene_io.h"

namespace pl {

namespace {

struct JobOutcome {
    double seconds = 0;
    size_t pixels = 0;
    std::string mode = "-";  // exact | statistical | missing | mismatch
    Comparison comparison;
    bool passed = true;
};

// The scene of a job, with the job's settings applied.
SceneDescription describeJob(const BatchJob& job, uint64_t seedOffset) {
    SceneDescription desc = parseScene(job.sceneFile);
    desc.render.spp = job.spp;
    desc.render.seed = job.seed + seedOffset;
    if (job.integrator) setIntegrator(desc.render, *job.integrator);
    if (job.channels) desc.render.channels = *job.channels;
    if (std::string why = refusalOf(desc.render); !why.empty())
        throw InputError(job.sceneFile.string(), why);
    return desc;
}

// Compares a fresh result with the stored one of the same name: bit for bit
// if the code, scene, seed, spp, integrator and channels are the same, else
// statistically (core/result_comparison.h).
void compareWithStored(const RadianceImage& fresh, size_t pixels, const std::vector<int>& channels,
                       const std::filesystem::path& storedFile, const ComparisonLimits& limits,
                       JobOutcome& out) {
    if (!std::filesystem::exists(storedFile)) {
        out.mode = "missing";
        out.passed = false;
        return;
    }
    RadianceImage stored = readExr(storedFile);
    bool sameRun = true;
    for (const char* key : {"code", "seed", "spp", "integrator", "channels", "scene"})
        sameRun = sameRun && stored.meta(key) == fresh.meta(key);
    if (stored.meta("pixels") != std::to_string(pixels) || stored.meta("channels") != fresh.meta("channels")) {
        out.mode = "mismatch";  // another sensor or other channels: nothing to compare
        out.passed = false;
        return;
    }
    auto samples = [](const RadianceImage& im) { return uint32_t(std::strtoul(im.meta("spp").c_str(), nullptr, 10)); };
    out.comparison = compareResults(pixelResultsOf(fresh, pixels), samples(fresh), pixelResultsOf(stored, pixels),
                                    samples(stored), channels, limits);
    out.mode = sameRun ? "exact" : "statistical";
    out.passed = sameRun ? out.comparison.bitIdentical : out.comparison.passes(limits);
}

std::string describeComparison(const JobOutcome& o, const std::vector<int>& channels) {
    if (o.mode == "missing") return "no stored result";
    if (o.mode == "mismatch") return "stored result is of another sensor or channels";
    const Comparison& c = o.comparison;
    std::ostringstream s;
    if (o.mode == "exact") {
        s << (c.bitIdentical ? "bit-identical" : "NOT bit-identical (same code and seed)");
        if (c.bitIdentical) return s.str();
        s << "; ";
    }
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.4f %% outliers", 100.0 * c.outlierFraction());
    s << buf;
    if (c.nonFinite) s << ", " << c.nonFinite << " NaN/Inf";
    s << ", bias";
    for (int ch : channels) {
        std::snprintf(buf, sizeof buf, " %c %+.3g (z %+.2f)", "rgb"[ch], c.bias[ch], c.biasZ[ch]);
        s << buf;
    }
    return s.str();
}

// Renders job j of the manifest, writes its result and compares it with
// the stored one: what it printed (printed at once with printNow), its CSV
// row and whether it passed.
nlohmann::json runJob(const BatchManifest& manifest, size_t j, SceneDescription& desc, const std::filesystem::path& dir,
                      const std::string& code, const std::optional<std::filesystem::path>& compareDir,
                      const ComparisonLimits& limits, bool quiet, bool printNow) {
    const BatchJob& job = manifest.jobs[j];
    auto t0 = std::chrono::steady_clock::now();
    Scene scene = loadScene(desc, sceneNeedsOf(desc.render));
    std::unique_ptr<Sensor> sensor = makeSensor(desc, scene);
    desc.render.showProgress = !quiet && ProgressBar::stderrIsTerminal();
    RenderResult result = render(scene, *sensor, desc.render);

    JobOutcome out;
    out.pixels = sensor->pixelCount();
    RadianceImage image = filmToPixelImage(result.film);
    // How it was made, as a render's image says (render/render_outputs.h),
    // with the scene's path as the manifest names it, the pixels and the code.
    image.metadata = renderMetadata(desc, desc.render.spp);
    for (auto& [key, value] : image.metadata)
        if (key == "scene") value = job.sceneFile.lexically_normal().string();
    image.metadata.push_back({"pixels", std::to_string(out.pixels)});
    image.metadata.push_back({"code", code});
    writeExr(image, dir / (job.name + ".exr"));
    out.seconds = secondsSince(t0);
    char line[512];
    std::snprintf(line, sizeof line, "batch [%zu/%zu] %s: %zu px x %u spp x %zu ch, %s, seed %llu, %.2f s\n", j + 1,
                  manifest.jobs.size(), job.name.c_str(), out.pixels, desc.render.spp,
                  desc.render.channels.size(), desc.render.integrator.c_str(),
                  (unsigned long long)desc.render.seed, out.seconds);
    std::string printed = line;
    if (compareDir) {
        compareWithStored(image, out.pixels, desc.render.channels, *compareDir / (job.name + ".exr"), limits, out);
        printed += "  compare (" + out.mode + "): " + describeComparison(out, desc.render.channels) + " -> " +
                   (out.passed ? "pass" : "FAIL") + "\n";
    }
    if (printNow) {
        std::fputs(printed.c_str(), stdout);
        std::fflush(stdout);
    }
    std::ostringstream row;
    row << job.name << ',' << job.sceneFile.string() << ',' << desc.render.integrator << ',' << desc.render.spp
        << ',' << desc.render.seed << ',' << channelNames(desc.render.channels) << ',' << out.pixels << ','
        << out.seconds << ',' << out.mode << ',' << out.comparison.outlierFraction();
    for (double b : out.comparison.bias) row << ',' << b;
    for (double z : out.comparison.biasZ) row << ',' << z;
    row << ',' << (compareDir ? (out.passed ? "pass" : "fail") : "-") << '\n';
    return {{"job", j}, {"passed", out.passed}, {"printed", printed}, {"row", row.str()}};
}

}  // namespace

int batchCommand(const std::vector<std::string>& argv) {
    Arguments args("batch", argv,
                   {{"-o,--output", "DIR", "where the results go (required)"},
                    {"--compare", "STORED_DIR", "check each result against a stored one: bit-identical for the same "
                                                "code and seed, else per-pixel t tests and a bias test; exit 1 on failure"},
                    kThreadsOption,
                    {"--seed-offset", "N", "added to every scene's seed"},
                    {"--max-outlier-fraction", "F", "share of pixels a comparison may fail (0..1)"},
                    kQuietOption});
    if (args.positional().size() != 1) throw UsageError("batch needs exactly one MANIFEST.json");
    auto outDir = args.value("-o");
    if (!outDir) throw UsageError("batch needs -o DIR for its results");
    std::optional<std::filesystem::path> compareDir;
    if (auto c = args.value("--compare")) compareDir = *c;
    uint64_t seedOffset = uint64_t(args.integer("--seed-offset", 0, int64_t(1) << 40).value_or(0));
    ThreadLimit threadLimit(args);
    ComparisonLimits limits;
    if (auto f = args.number("--max-outlier-fraction")) {
        limits.maxOutlierFraction = *f;
        if (!(limits.maxOutlierFraction >= 0 && limits.maxOutlierFraction <= 1))
            throw UsageError("--max-outlier-fraction must be a number in 0..1");
    }
    bool quiet = args.has("--quiet");

    // Read and check everything before the first (possibly long) render.
    BatchManifest manifest = parseBatchManifest(args.positional()[0]);
    std::vector<SceneDescription> descs;
    std::filesystem::path dir = *outDir;
    for (const BatchJob& job : manifest.jobs) {
        descs.push_back(describeJob(job, seedOffset));
        std::vector<std::filesystem::path> inputs = descs.back().inputFiles();
        inputs.push_back(manifest.file);
        if (compareDir) inputs.push_back(*compareDir / (job.name + ".exr"));
        refuseToOverwriteInputs(dir / (job.name + ".exr"), inputs);
    }
    if (compareDir && std::filesystem::exists(*compareDir) && std::filesystem::exists(dir) &&
        std::filesystem::equivalent(*compareDir, dir))
        throw UsageError("-o and --compare name the same directory (the stored results would be overwritten)");
    std::filesystem::create_directories(dir);

    // Under MPI the jobs are dealt round the ranks; each writes its own
    // results and rank 0 gathers what each job printed and its CSV row.
    const int rank = Distributed::rank(), ranks = Distributed::ranks();
    std::string code = codeFingerprint();
    nlohmann::json done = nlohmann::json::array();
    runOnEveryRank([&] {  // a failure on any rank stops them all; rank 0 says which
        for (size_t j = size_t(rank); j < manifest.jobs.size(); j += size_t(ranks))
            done.push_back(runJob(manifest, j, descs[j], dir, code, compareDir, limits, quiet, ranks == 1));
    });
    const std::vector<std::string> fromRanks = gatherTextOnRankZero(done.dump());
    if (rank != 0) return 0;

    // In job order, whichever rank rendered each.
    std::vector<nlohmann::json> byJob(manifest.jobs.size());
    for (const std::string& text : fromRanks)
        for (const auto& entry : nlohmann::json::parse(text)) byJob[entry["job"].get<size_t>()] = entry;
    bool allPassed = true;
    std::ostringstream csv;
    csv << "name,scene,integrator,spp,seed,channels,pixels,seconds,compare,outlier_fraction,"
           "bias_r,bias_g,bias_b,bias_z_r,bias_z_g,bias_z_b,verdict\n";
    for (const nlohmann::json& entry : byJob) {
        if (ranks > 1) std::fputs(entry["printed"].get<std::string>().c_str(), stdout);
        csv << entry["row"].get<std::string>();
        allPassed = allPassed && entry["passed"].get<bool>();
    }
    writeTextFile(dir / "batch.csv", csv.str());
    if (compareDir)
        std::printf("batch: %s against %s\n", allPassed ? "all results agree" : "REGRESSION", compareDir->string().c_str());
    return allPassed ? 0 : 1;
}

}  // namespace pl
