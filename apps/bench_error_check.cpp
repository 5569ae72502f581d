#include "apps/bench_error_check.h"

#include <cstdio>
#include <sstream>

#include "compare/error_calibration.h"
#include "runtime/distributed.h"

namespace pl {

std::string errorCheckTable(const Scene& scene, const Sensor& sensor,
                            const std::vector<std::pair<std::string, RenderSettings>>& configurations,
                            const std::vector<uint32_t>& spps, uint64_t seed, bool acrossRanks) {
    std::ostringstream md;
    md << "Two renders per row (seeds " << seed << " and " << seed + 1
       << "), z = (a - b) / sqrt(se_a^2 + se_b^2) per pixel and channel; honest errors give a mean z^2 near 1 and "
          "|z| > 4 in about 6e-5 of the values.\n\n";
    md << "| config | spp | time (s) | mean z^2 R | mean z^2 G | mean z^2 B | \\|z\\| > 4 | error 0 where they differ |\n";
    md << "|---|---|---|---|---|---|---|---|\n";
    for (const auto& [name, settings] : configurations)
        for (uint32_t spp : spps) {
            RenderSettings s = settings;
            s.spp = spp;
            s.seed = seed;
            RenderResult a = render(scene, sensor, s, acrossRanks);
            s.seed = seed + 1;
            RenderResult b = render(scene, sensor, s, acrossRanks);
            if (Distributed::rank() != 0) continue;
            const ErrorCalibration e = calibrateErrors(a.film, b.film);
            char line[512];
            std::snprintf(line, sizeof line, "| %s | %u | %.2f | %.3g | %.3g | %.3g | %.3f %% | %.3f %% |\n",
                          name.c_str(), spp, 0.5 * (a.seconds + b.seconds), e.meanZSq[0], e.meanZSq[1], e.meanZSq[2],
                          100.0 * e.shareBeyondFour(), 100.0 * e.shareZeroErrorButDiffer());
            md << line;
            std::fprintf(stderr, "bench: %s", line);
        }
    return md.str();
}

}  // namespace pl
