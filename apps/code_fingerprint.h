// Identifies the running program's code: a hash of its executable file.
// Batch regression renders demand bit-identical results when the code (and
// the seed) are the same, and compare statistically otherwise.
#pragma once

#include <string>

namespace pl {

// 16 hex digits (FNV-1a over /proc/self/exe), or "unknown" if unreadable.
std::string codeFingerprint();

}  // namespace pl
