// Errors in user input. The message names the file and the problem on one
// line; the apps print it and exit non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace pl {

struct InputError : std::runtime_error {
    InputError(const std::string& file, const std::string& problem)
        : std::runtime_error(file + ": " + problem) {}
};

}  // namespace pl
