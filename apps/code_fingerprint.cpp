#include "apps/code_fingerprint.h"

#include <cinttypes>
#include <cstdio>
#include <fstream>
#include <vector>

namespace pl {

std::string codeFingerprint() {
    std::ifstream in("/proc/self/exe", std::ios::binary);
    if (!in) return "unknown";
    uint64_t h = 1469598103934665603ull;
    std::vector<char> buf(1 << 16);
    while (in.read(buf.data(), std::streamsize(buf.size())) || in.gcount() > 0) {
        for (std::streamsize i = 0; i < in.gcount(); ++i) {
            h ^= uint8_t(buf[size_t(i)]);
            h *= 1099511628211ull;
        }
    }
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016" PRIx64, h);
    return hex;
}

}  // namespace pl
