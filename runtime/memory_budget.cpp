#include "runtime/memory_budget.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

namespace pl {

namespace {
std::string gib(uint64_t bytes) {
    char buf[32];
    if (bytes >= (1ull << 30)) std::snprintf(buf, sizeof buf, "%.2f GiB", double(bytes) / double(1ull << 30));
    else std::snprintf(buf, sizeof buf, "%.1f MiB", double(bytes) / double(1ull << 20));
    return buf;
}
}  // namespace

uint64_t memoryBudgetBytes() {
    if (const char* env = std::getenv("PRINTLIGHT_MEMORY_LIMIT_MB")) {
        char* end = nullptr;
        unsigned long long mb = std::strtoull(env, &end, 10);
        if (end != env && *end == '\0' && mb > 0) return uint64_t(mb) << 20;
    }
    long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGE_SIZE);
    uint64_t physical = pages > 0 && pageSize > 0 ? uint64_t(pages) * uint64_t(pageSize) : UINT64_MAX;
    // cgroup v2 limit ("max" when there is none).
    std::ifstream cg("/sys/fs/cgroup/memory.max");
    unsigned long long limit = 0;
    if (cg >> limit && limit > 0 && limit < physical) return limit;
    return physical;
}

uint64_t memoryInUseBytes() {
    std::ifstream statm("/proc/self/statm");
    unsigned long long pages = 0, resident = 0;
    if (!(statm >> pages >> resident)) return 0;
    return uint64_t(resident) * uint64_t(sysconf(_SC_PAGE_SIZE));
}

uint64_t itemsTheMemoryHolds(uint64_t bytesEach) {
    const uint64_t budget = memoryBudgetBytes(), inUse = memoryInUseBytes();
    return budget > inUse ? (budget - inUse) / bytesEach : 0;
}

std::optional<std::string> memoryShortfall(uint64_t bytes, const std::string& what, uint64_t inUse,
                                           const std::string& remedy) {
    uint64_t budget = memoryBudgetBytes();
    if (bytes + inUse <= budget) return std::nullopt;
    std::string line = what + " needs about " + gib(bytes) + " of memory";
    if (inUse) line += " besides the " + gib(inUse) + " in use";
    line += "; this machine has " + gib(budget) + " (refused before allocating)";
    if (!remedy.empty()) line += ": " + remedy;
    return line;
}

}  // namespace pl
