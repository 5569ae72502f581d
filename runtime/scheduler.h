// The tile scheduler: TBB owns all parallelism. Work is cut into fixed
// tiles of consecutive pixels; each tile is processed by one thread, so
// everything below is per-thread and lock-free, and results depend only on
// the pixel, never on which thread ran it.
#pragma once

#include <cstddef>
#include <functional>

namespace pl {

void parallelForTiles(size_t count, size_t tileSize,
                      const std::function<void(size_t begin, size_t end)>& body);

}  // namespace pl
