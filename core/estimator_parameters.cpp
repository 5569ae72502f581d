#include "core/estimator_parameters.h"

#include <algorithm>
#include <cstdint>

namespace pl {

const ParameterInfo* findParameter(const std::vector<ParameterInfo>& infos, const std::string& name) {
    auto it = std::find_if(infos.begin(), infos.end(), [&](const ParameterInfo& i) { return i.name == name; });
    return it == infos.end() ? nullptr : &*it;
}

void EstimatorParameters::keepOnly(const std::vector<ParameterInfo>& infos) {
    auto unread = [&](const auto& entry) { return !findParameter(infos, entry.first); };
    for (auto it = numbers_.begin(); it != numbers_.end();) it = unread(*it) ? numbers_.erase(it) : std::next(it);
    for (auto it = texts_.begin(); it != texts_.end();) it = unread(*it) ? texts_.erase(it) : std::next(it);
}

namespace {

// As setOption (core/option_table.h) checks a value: the same range test.
std::string rangeProblem(const ParameterInfo& info, double value) {
    using Kind = ParameterInfo::Kind;
    if (info.kind == Kind::Boolean) return "";
    return inOptionRange(value, info.min, info.max, info.minOpen, info.kind == Kind::Integer, info.singlePrecision)
               ? ""
               : info.rangeText;
}

}  // namespace

std::optional<ParameterProblem> checkParameters(const std::vector<ParameterInfo>& infos,
                                                const EstimatorParameters& parameters, const std::string& estimator) {
    auto unknown = [&](const std::string& name) {
        std::string keys;
        for (const ParameterInfo& i : infos) keys += (keys.empty() ? "" : ", ") + i.name;
        return ParameterProblem{name, "not an option of " + estimator + " (" +
                                          (keys.empty() ? "it takes none" : "its options: " + keys) + ")"};
    };
    for (const auto& [name, value] : parameters.numbers()) {
        const ParameterInfo* info = findParameter(infos, name);
        if (!info) return unknown(name);
        if (info->isText()) return ParameterProblem{name, "must be a name or a path, not a number"};
        if (std::string problem = rangeProblem(*info, value); !problem.empty()) return ParameterProblem{name, problem};
    }
    for (const auto& [name, text] : parameters.texts()) {
        const ParameterInfo* info = findParameter(infos, name);
        if (!info) return unknown(name);
        if (!info->isText()) return ParameterProblem{name, "must be a number"};
        if (info->kind == ParameterInfo::Kind::Name &&
            std::find(info->names.begin(), info->names.end(), text) == info->names.end())
            return ParameterProblem{name, info->rangeText};
    }
    return std::nullopt;
}

}  // namespace pl
