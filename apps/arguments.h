// A tiny command-line reader: positional arguments and --key value options.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "core/vecmath.h"

namespace pl {

class Arguments {
public:
    // valueOptions take a value; flagOptions do not.
    Arguments(const std::vector<std::string>& args, std::set<std::string> valueOptions,
              std::set<std::string> flagOptions) {
        for (size_t i = 0; i < args.size(); ++i) {
            const std::string& a = args[i];
            if (a.size() > 1 && a[0] == '-') {
                if (valueOptions.count(a)) {
                    if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
                    values_[a] = args[++i];
                } else if (flagOptions.count(a)) {
                    values_[a] = "";
                } else {
                    throw UsageError("unknown option '" + a + "'");
                }
            } else {
                positional_.push_back(a);
            }
        }
    }
    const std::vector<std::string>& positional() const { return positional_; }
    bool has(const std::string& k) const { return values_.count(k) != 0; }
    std::optional<std::string> value(const std::string& k) const {
        auto it = values_.find(k);
        return it == values_.end() ? std::nullopt : std::optional<std::string>(it->second);
    }
    std::optional<int64_t> integer(const std::string& k, int64_t lo, int64_t hi) const {
        auto v = value(k);
        if (!v) return std::nullopt;
        size_t used = 0;
        int64_t x = 0;
        try {
            x = std::stoll(*v, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used != v->size() || x < lo || x > hi)
            throw UsageError(k + " must be an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
        return x;
    }

private:
    std::vector<std::string> positional_;
    std::map<std::string, std::string> values_;
};

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
