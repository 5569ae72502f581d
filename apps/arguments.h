// A command's command line, read with CLI11: its operands (positional
// arguments) and options, each declared with what it does, so that
// `printlight COMMAND --help` lists them. A usage error is one line that
// names the option and points at `printlight COMMAND --help`.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "core/vecmath.h"

namespace pl {

struct Option {
    std::string names;      // "--spp", or "-o,--output" (looked up by the first)
    std::string valueName;  // what the value is, e.g. "N" or "FILE"; empty for a flag
    std::string help;
};

class Arguments {
public:
    // Parses args for the command named `command` (commands.h); throws
    // HelpRequested for --help and UsageError for anything it cannot read.
    Arguments(const std::string& command, const std::vector<std::string>& args, const std::vector<Option>& options);
    const std::vector<std::string>& positional() const { return positional_; }
    bool has(const std::string& name) const { return values_.count(name) != 0; }
    std::optional<std::string> value(const std::string& name) const {
        auto it = values_.find(name);
        return it == values_.end() ? std::nullopt : std::optional<std::string>(it->second);
    }
    std::optional<int64_t> integer(const std::string& name, int64_t lo, int64_t hi) const;
    // The option's value as a number (UsageError "NAME takes a number" if
    // it is not one); the range is the caller's to check.
    std::optional<double> number(const std::string& name) const;

private:
    std::vector<std::string> positional_;
    std::map<std::string, std::string> values_;  // by the option's first name; "" for a flag
};

// The parts of a list option's value, e.g. "a,b,c" (empty parts kept).
inline std::vector<std::string> splitList(const std::string& text, char sep = ',') {
    std::vector<std::string> parts;
    std::stringstream in(text);
    for (std::string part; std::getline(in, part, sep);) parts.push_back(part);
    return parts;
}

// "x,y,z" as three numbers (UsageError naming the option otherwise).
inline Vec3f parseTriple(const std::string& option, const std::string& text) {
    Vec3f v;
    std::istringstream in(text);
    char c1 = 0, c2 = 0;
    if (!(in >> v.x >> c1 >> v.y >> c2 >> v.z) || c1 != ',' || c2 != ',' || !in.eof())
        throw UsageError(option + " takes three comma-separated numbers, e.g. 0.0423,0.0847,0.027");
    return v;
}

}  // namespace pl
