// Linear RGB triple: radiance, coefficients per channel.
#pragma once

#include <array>

namespace pl {

constexpr int kChannels = 3;
using RGB = std::array<float, kChannels>;

}  // namespace pl
