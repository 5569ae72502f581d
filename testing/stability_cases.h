// The numerical stability suite (printlight stability, docs/stability.md):
// stiff and extreme scenes (docs/stability.md), each rendered with volpath
// and printpt and checked against a value whose origin is known: a closed
// form, the furnace, Beer-Lambert, the other estimator, or the same scene
// at the origin.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pl {

struct StabilityRow {
    std::string caseName, parameters, estimator;
    std::string source;        // where the expected value comes from
    double expected = 0, expectedStdErr = 0;
    double measured = 0, stdErr = 0;
    double z = 0;              // (measured - expected) / combined standard error
    uint64_t nonFinite = 0;    // pixel values that are NaN or Inf
    uint64_t paths = 0, leaks = 0, trapped = 0;
    double maxLeakFraction = 1e-3;  // numerical leaks allowed, per path
    double seconds = 0;
    bool pass = false;
    std::string note;
};

// Rows whose |z| stays below this pass (with ~50 rows, a false alarm
// somewhere has probability ~3e-3).
constexpr double kStabilityZLimit = 4.0;

// Runs every case (quick: a subset with fewer samples, for ctest).
// `progress` is called after each row.
std::vector<StabilityRow> runStabilitySuite(bool quick, uint64_t seed,
                                            const std::function<void(const StabilityRow&)>& progress);

}  // namespace pl
