// Ctrl-C (SIGINT) and SIGTERM: long jobs stop at the next sample, write
// nothing under the output name and exit with 130. A second signal (more
// than 0.2 s after the first: tools like timeout(1) deliver one request
// twice) ends the process at once.
#pragma once

#include <stdexcept>

namespace pl {

// Installs the handlers (idempotent).
void installInterruptHandler();
// Whether a stop was requested (cheap: one relaxed atomic load).
bool interruptRequested();

// Thrown by a job that stopped because of a signal.
struct Interrupted : std::runtime_error {
    Interrupted() : std::runtime_error("interrupted") {}
};

// Throws Interrupted if a stop was requested.
inline void throwIfInterrupted() {
    if (interruptRequested()) throw Interrupted();
}

}  // namespace pl
