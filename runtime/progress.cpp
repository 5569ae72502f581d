#include "runtime/progress.h"

#include <unistd.h>

#include <cstdio>

namespace pl {

namespace {
std::string formatDuration(double s) {
    int total = int(s + 0.5);
    char buf[32];
    if (total >= 3600)
        std::snprintf(buf, sizeof buf, "%d:%02d:%02d", total / 3600, total / 60 % 60, total % 60);
    else
        std::snprintf(buf, sizeof buf, "%02d:%02d", total / 60, total % 60);
    return buf;
}
}  // namespace

bool ProgressBar::stderrIsTerminal() { return isatty(STDERR_FILENO) != 0; }

ProgressBar::ProgressBar(uint64_t total, std::string label, bool enabled)
    : total_(total), label_(std::move(label)), enabled_(enabled) {
    start_ = lastDraw_ = std::chrono::steady_clock::now();
}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::advance(uint64_t n) {
    uint64_t done = done_.fetch_add(n) + n;
    if (!enabled_) return;
    auto now = std::chrono::steady_clock::now();
    // Redraw at most ten times a second; never block a worker on the lock.
    std::unique_lock<std::mutex> lock(drawMutex_, std::try_to_lock);
    if (!lock.owns_lock() || now - lastDraw_ < std::chrono::milliseconds(100)) return;
    lastDraw_ = now;
    draw(done);
}

void ProgressBar::draw(uint64_t done) {
    double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    double frac = total_ ? double(done) / double(total_) : 1.0;
    const int width = 30;
    int filled = int(frac * width);
    std::string bar(size_t(filled), '=');
    if (filled < width) bar += '>' + std::string(size_t(width - filled - 1), ' ');
    std::string eta = frac > 0 ? formatDuration(elapsed * (1.0 - frac) / frac) : "--:--";
    std::fprintf(stderr, "\r%s [%s] %5.1f%%  %s elapsed, ETA %s ", label_.c_str(), bar.c_str(),
                 100.0 * frac, formatDuration(elapsed).c_str(), eta.c_str());
    std::fflush(stderr);
}

void ProgressBar::finish() {
    if (finished_) return;
    finished_ = true;
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(drawMutex_);
    draw(done_.load());
    std::fprintf(stderr, "\n");
}

}  // namespace pl
