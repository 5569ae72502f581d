// A progress bar with ETA on stderr; silent when stderr is not a terminal.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace pl {

// Wall-clock seconds since t.
inline double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

class ProgressBar {
public:
    ProgressBar(uint64_t total, std::string label, bool enabled);
    ~ProgressBar();
    void advance(uint64_t n);
    void finish();
    static bool stderrIsTerminal();

private:
    void draw(uint64_t done);

    uint64_t total_;
    std::string label_;
    bool enabled_;
    std::atomic<uint64_t> done_{0};
    std::mutex drawMutex_;
    std::chrono::steady_clock::time_point start_, lastDraw_;
    bool finished_ = false;
};

}  // namespace pl
