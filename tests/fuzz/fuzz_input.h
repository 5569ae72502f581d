// libFuzzer harness helpers: the readers take files, so each input is
// written to a per-process temporary file first. A reader may reject the
// input only with InputError; anything else (another exception, a crash, a
// sanitizer report, a hang, running out of memory) is a finding.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace pl::fuzz {

inline std::filesystem::path writeInput(const uint8_t* data, size_t size, const std::string& extension) {
    const std::filesystem::path file =
        std::filesystem::temp_directory_path() / ("printlight_fuzz_" + std::to_string(::getpid()) + extension);
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    return file;
}

}  // namespace pl::fuzz
