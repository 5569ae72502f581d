// Whether reported standard errors are honest: two independent renders of
// the same sensor, each with its own errors, compared value by value,
// z = (a - b) / sqrt(se_a^2 + se_b^2). With honest errors the mean of z^2
// is about 1 and |z| > 4 almost never happens (6.3e-5 of a normal's
// values); errors that are too small show as a large mean z^2 and heavy
// tails, errors that are too large as a mean z^2 well below 1.
#pragma once

#include <array>
#include <cstddef>

#include "compare/result_comparison.h"
#include "core/film.h"

namespace pl {

struct ErrorCalibration {
    size_t values = 0;                  // pixel channels compared (covered in both)
    std::array<double, 3> meanZSq{};    // per channel, over the values with a combined error
    std::array<size_t, 3> perChannel{};  // values per channel
    size_t beyondFour = 0;              // values with |z| > 4
    size_t zeroErrorButDiffer = 0;      // combined error 0 where the renders differ
    double shareBeyondFour() const { return values ? double(beyondFour) / double(values) : 0.0; }
    double shareZeroErrorButDiffer() const { return values ? double(zeroErrorButDiffer) / double(values) : 0.0; }
};

// Compares a and b (same pixels) over the pixels `covered` marks (all when
// empty). A difference with a combined error of 0 counts beyond four.
ErrorCalibration calibrateErrors(const PixelResults& a, const PixelResults& b, const std::vector<bool>& covered = {});
// The same for two films, over the pixels with samples in both.
ErrorCalibration calibrateErrors(const Film& a, const Film& b);

}  // namespace pl
