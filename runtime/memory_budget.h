// Refusing jobs that cannot fit: the memory a job will need is estimated
// before the big allocations and compared with what the machine has.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace pl {

// Physical memory, or the cgroup (container) limit if lower; the
// environment variable PRINTLIGHT_MEMORY_LIMIT_MB overrides both (tests,
// shared machines).
uint64_t memoryBudgetBytes();

// The process's resident memory now (0 where /proc is not there).
uint64_t memoryInUseBytes();

// How many items of `bytesEach` the memory left now (the budget less the
// memory in use) holds.
uint64_t itemsTheMemoryHolds(uint64_t bytesEach);

// A one-line explanation if `bytes` (needed for `what`, on top of
// `inUse`) exceeds the budget; `remedy` (if any) says what would fit.
std::optional<std::string> memoryShortfall(uint64_t bytes, const std::string& what, uint64_t inUse = 0,
                                           const std::string& remedy = "");

}  // namespace pl
