#include "core/interrupt.h"

#include <atomic>
#include <csignal>
#include <unistd.h>

namespace pl {

namespace {
std::atomic<bool> gStop{false};

extern "C" void onSignal(int) {
    if (gStop.exchange(true)) _exit(130);  // the second signal: stop now
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
