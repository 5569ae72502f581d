// printpt's switches by their scene-file names (render.<key>, documented in
// docs/scene-format.md): one table for the scene parser and for bench's
// "printpt/key=value" configurations.
#pragma once

#include <string>
#include <vector>

#include "integrators/printpt.h"

namespace pl {

struct PrintPtKey {
    enum class Kind { Boolean, Integer, Number };
    const char* name;
    Kind kind;
};

const std::vector<PrintPtKey>& printPtKeys();

// Sets the switch `key` (booleans: value != 0). Returns what is wrong with
// the value ("must be in (0, 1]"), or "" if it was set; throws
// std::invalid_argument for a key that is not in printPtKeys().
std::string setPrintPtOption(PrintPtOptions& options, const std::string& key, double value);

}  // namespace pl
