#include "runtime/scheduler.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace pl {

void parallelForTiles(size_t count, size_t tileSize,
                      const std::function<void(size_t, size_t)>& body) {
    size_t tiles = (count + tileSize - 1) / tileSize;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles, 1),
                      [&](const tbb::blocked_range<size_t>& r) {
                          for (size_t t = r.begin(); t != r.end(); ++t)
                              body(t * tileSize, std::min(count, (t + 1) * tileSize));
                      });
}

}  // namespace pl
