// Small helpers on file names.
#pragma once

#include <cctype>
#include <filesystem>
#include <string>

namespace pl {

// ".VDB" -> ".vdb": formats are chosen by extension, case-insensitively.
inline std::string lowerExtension(const std::filesystem::path& p) {
    std::string e = p.extension().string();
    for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

}  // namespace pl
