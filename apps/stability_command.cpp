// printlight stability: runs the numerical stability suite and writes its
// table (docs/stability.md is this command's output).

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "apps/arguments.h"
#include "apps/command_options.h"
#include "testing/stability_cases.h"
#include "runtime/progress.h"
#include "io/output_file.h"

namespace pl {

namespace {

std::string number(double v) {
    char buf[32];
    if (v != 0 && (std::abs(v) < 1e-3 || std::abs(v) >= 1e5)) std::snprintf(buf, sizeof buf, "%.4e", v);
    else std::snprintf(buf, sizeof buf, "%.6f", v);
    return buf;
}

std::string markdownTable(const std::vector<StabilityRow>& rows, bool quick, int threads, double seconds) {
    std::ostringstream md;
    int failed = 0;
    for (const auto& r : rows) failed += !r.pass;
    md << "# Numerical stability suite\n\n"
       << "Written by `printlight stability" << (quick ? " --quick" : "") << " -o docs/stability.md` ("
       << threads << " thread(s), " << number(seconds) << " s in all). Every stiff or extreme case on small "
       << "scenes built in code (`testing/stability_cases.cpp`), rendered with volpath (no re-entry) and printpt "
       << "(defaults), channel r. *measured* is the mean over all pixels, *std err* its standard error "
       << "(pixels are independent); *z* = (measured - expected) / the combined standard error (round-off "
       << "of 1e-6 relative allowed where both are deterministic); a row passes with |z| < " << kStabilityZLimit
       << ", no NaN/Inf, no trapped path, and numerical leaks (a collision within float round-off of the boundary that lands on its far side: the path leaves, as it nearly did) below 1e-3 of the paths (wedge: 4x the share of rays through the edge thinner than the ray offset).\n\n"
       << "**" << rows.size() - size_t(failed) << " of " << rows.size() << " rows pass.**\n\n"
       << "| case | parameters | estimator | expected (source) | measured | std err | z | NaN/Inf | leaks / paths | time s | verdict |\n"
       << "|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& r : rows) {
        md << "| " << r.caseName << " | " << r.parameters << " | " << r.estimator << " | ";
        if (r.estimator == "load") {
            md << r.source << " | " << r.note << " | | | | | | " << (r.pass ? "pass" : "**FAIL**") << " |\n";
            continue;
        }
        md << number(r.expected);
        if (r.expectedStdErr > 0) md << " +- " << number(r.expectedStdErr);
        md << " (" << r.source << ") | " << number(r.measured) << " | " << number(r.stdErr) << " | ";
        char z[32];
        std::snprintf(z, sizeof z, "%+.2f", r.z);
        md << z << " | " << r.nonFinite << " | " << r.leaks << " / " << r.paths << " | ";
        char t[32];
        std::snprintf(t, sizeof t, "%.2f", r.seconds);
        md << t << " | " << (r.pass ? "pass" : "**FAIL**") << (r.note.empty() ? "" : " (" + r.note + ")") << " |\n";
    }
    return md.str();
}

}  // namespace

int stabilityCommand(const std::vector<std::string>& argv) {
    Arguments args("stability", argv,
                   {{"-o,--output", "REPORT.md", "the report (default docs/stability.md if ./docs exists, else stability.md)"},
                    kSeedOption, kThreadsOption,
                    {"--quick", "", "a shorter suite"}});
    if (!args.positional().empty()) throw UsageError("stability takes no positional arguments");
    bool quick = args.has("--quick");
    uint64_t seed = uint64_t(args.integer("--seed", 0, RenderSettings::kMostSeed).value_or(1));
    ThreadLimit threads(args);
    auto t0 = std::chrono::steady_clock::now();
    std::vector<StabilityRow> rows = runStabilitySuite(quick, seed, [](const StabilityRow& r) {
        std::printf("%-28s %-8s expected %-12s measured %-12s z %+6.2f  NaN %llu  %6.2f s  %s%s\n", r.caseName.c_str(),
                    r.estimator.c_str(), number(r.expected).c_str(), number(r.measured).c_str(), r.z,
                    (unsigned long long)r.nonFinite, r.seconds, r.pass ? "pass" : "FAIL",
                    r.note.empty() ? "" : ("  " + r.note).c_str());
        std::fflush(stdout);
    });
    int failed = 0;
    for (const auto& r : rows) failed += !r.pass;
    // Default: the repository's report when run from its root.
    std::string out = args.value("-o").value_or(std::filesystem::is_directory("docs") ? "docs/stability.md" : "stability.md");
    writeTextFile(out, markdownTable(rows, quick, threads.count, secondsSince(t0)));
    std::printf("stability: %zu of %zu rows pass (%.1f s) -> %s\n", rows.size() - size_t(failed), rows.size(),
                secondsSince(t0), out.c_str());
    return failed ? 1 : 0;
}

}  // namespace pl
