// Base64 (RFC 4648, padded): glTF's embedded buffers, the report's models.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace pl {

inline std::string base64(const unsigned char* bytes, size_t size) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((size + 2) / 3 * 4);
    for (size_t i = 0; i < size; i += 3) {
        uint32_t v = uint32_t(bytes[i]) << 16;
        if (i + 1 < size) v |= uint32_t(bytes[i + 1]) << 8;
        if (i + 2 < size) v |= bytes[i + 2];
        out += table[(v >> 18) & 63];
        out += table[(v >> 12) & 63];
        out += i + 1 < size ? table[(v >> 6) & 63] : '=';
        out += i + 2 < size ? table[v & 63] : '=';
    }
    return out;
}

}  // namespace pl
