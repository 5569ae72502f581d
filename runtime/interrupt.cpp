#include "runtime/interrupt.h"

#include <atomic>
#include <csignal>
#include <cstdint>
#include <ctime>
#include <unistd.h>

namespace pl {

namespace {

// Signals this close together are one request.
constexpr int64_t kSameRequest_ns = 200000000;

std::atomic<bool> gStop{false};
std::atomic<int64_t> gFirstSignal_ns{0};

int64_t monotonic_ns() {
    timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);  // async-signal-safe
    return int64_t(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

extern "C" void onSignal(int) {
    const int64_t now = monotonic_ns();
    int64_t first = 0;
    if (gFirstSignal_ns.compare_exchange_strong(first, now)) {
        gStop.store(true);
        return;
    }
    // A second signal stops at once, unless it is the first one delivered
    // twice: timeout(1) signals the process and then its process group.
    if (now - first > kSameRequest_ns) _exit(130);
}
}  // namespace

void installInterruptHandler() {
    struct sigaction sa {};
    sa.sa_handler = onSignal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

bool interruptRequested() { return gStop.load(std::memory_order_relaxed); }

}  // namespace pl
