#include "integrators/path_footprints.h"

#include <algorithm>
#include <iterator>

namespace pl {

void PathFootprints::add(size_t pixel, std::vector<uint32_t>& bricks) {
    std::sort(bricks.begin(), bricks.end());
    bricks.erase(std::unique(bricks.begin(), bricks.end()), bricks.end());
    std::vector<uint32_t>& held = bricks_[pixel];
    if (held.empty()) {
        held.assign(bricks.begin(), bricks.end());
        return;
    }
    std::vector<uint32_t> both;
    both.reserve(held.size() + bricks.size());
    std::set_union(held.begin(), held.end(), bricks.begin(), bricks.end(), std::back_inserter(both));
    held.swap(both);
    held.shrink_to_fit();
}

uint64_t PathFootprints::memoryBytes() const {
    uint64_t bytes = bricks_.capacity() * sizeof(bricks_[0]);
    for (const auto& b : bricks_) bytes += b.capacity() * sizeof(uint32_t);
    return bytes;
}

}  // namespace pl
