// The render block's keys that belong to the chosen estimator, as given
// (in the spirit of pbrt-v4's ParameterDictionary): numbers and booleans
// as numbers, names and paths as text. Each estimator declares what it
// reads (a list of ParameterInfo, made from its option tables) and reads
// its own in its factory (readOptions); the driver refuses a key the
// estimator does not declare, or a value out of its range, before any
// estimator is made (checkParameters).
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "core/option_table.h"

namespace pl {

struct ParameterInfo;

class EstimatorParameters {
  public:
    void set(const std::string& name, double value) { numbers_[name] = value; }
    void setText(const std::string& name, const std::string& text) { texts_[name] = text; }
    const std::map<std::string, double>& numbers() const { return numbers_; }
    const std::map<std::string, std::string>& texts() const { return texts_; }
    const double* number(const std::string& name) const {
        auto it = numbers_.find(name);
        return it == numbers_.end() ? nullptr : &it->second;
    }
    const std::string* text(const std::string& name) const {
        auto it = texts_.find(name);
        return it == texts_.end() ? nullptr : &it->second;
    }
    // Drops the keys `infos` does not name (another estimator's).
    void keepOnly(const std::vector<ParameterInfo>& infos);
    bool operator==(const EstimatorParameters& o) const {
        return numbers_ == o.numbers_ && texts_ == o.texts_ && materialsFile == o.materialsFile;
    }
    bool operator!=(const EstimatorParameters& o) const { return !(*this == o); }

    // Where the scene's material table is: the files an estimator keeps
    // beside it (the learned model) are found from it, as pbrt-v4's
    // dictionary resolves file names against the scene's folder. Paths in
    // texts are absolute or relative to the working directory (the scene
    // parser resolves them).
    std::filesystem::path materialsFile;

  private:
    std::map<std::string, double> numbers_;
    std::map<std::string, std::string> texts_;
};

// One key an estimator reads: its name, what it holds and its range, for
// the driver's checks, the scene writer and the docs' test.
struct ParameterInfo {
    enum class Kind { Boolean, Integer, Number, Name, Path };
    std::string name;
    Kind kind = Kind::Number;
    std::string doc;
    double min = 0, max = 0;
    bool minOpen = false;
    bool singlePrecision = false;    // a float field: checked as it will hold the value
    std::string rangeText;           // numbers: "must be ..."
    std::vector<std::string> names;  // Name: the values it takes
    bool isText() const { return kind == Kind::Name || kind == Kind::Path; }
};

// The keys of an option table.
template <class Options>
std::vector<ParameterInfo> describe(const std::vector<OptionParameter<Options>>& table) {
    using Kind = typename OptionParameter<Options>::Kind;
    std::vector<ParameterInfo> infos;
    for (const OptionParameter<Options>& p : table) {
        const ParameterInfo::Kind kind = p.kind() == Kind::Boolean   ? ParameterInfo::Kind::Boolean
                                         : p.kind() == Kind::Integer ? ParameterInfo::Kind::Integer
                                                                     : ParameterInfo::Kind::Number;
        const bool single = std::holds_alternative<float Options::*>(p.field);
        infos.push_back({p.name, kind, p.doc, p.min, p.max, p.minOpen, single, p.rangeText, {}});
    }
    return infos;
}

// A key whose value is one of an enum's names.
template <class Enum, size_t N>
ParameterInfo describeChoice(const char* name, const std::array<EnumName<Enum>, N>& names, const char* doc) {
    ParameterInfo info{name, ParameterInfo::Kind::Name, doc, 0, 0, false, false, "must be " + enumNames(names), {}};
    for (const EnumName<Enum>& n : names) info.names.push_back(n.name);
    return info;
}

// The options the table names, from the parameters over `options`' values.
// checkParameters refuses a value out of range first; settings made in
// code that skip it get std::invalid_argument here, never a default.
template <class Options>
Options readOptions(const std::vector<OptionParameter<Options>>& table, const EstimatorParameters& parameters,
                    Options options = {}) {
    for (const OptionParameter<Options>& p : table)
        if (const double* value = parameters.number(p.name))
            if (std::string problem = setOption(p, options, *value); !problem.empty())
                throw std::invalid_argument(std::string(p.name) + ": " + problem);
    return options;
}

// The inverse, for callers that hold options: each option that differs
// from the defaults, as the table names it.
template <class Options>
void writeOptions(const std::vector<OptionParameter<Options>>& table, const Options& options,
                  EstimatorParameters& parameters) {
    static const Options defaults{};
    for (const OptionParameter<Options>& p : table)
        if (optionValue(p, options) != optionValue(p, defaults)) parameters.set(p.name, optionValue(p, options));
}

// The enum's value the parameter names, or `byDefault` without one.
template <class Enum, size_t N>
Enum readChoice(const char* name, const std::array<EnumName<Enum>, N>& names, const EstimatorParameters& parameters,
                Enum byDefault) {
    const std::string* text = parameters.text(name);
    if (!text) return byDefault;
    return parseEnum(names, *text).value_or(byDefault);
}

// The key of that name, or none.
const ParameterInfo* findParameter(const std::vector<ParameterInfo>& infos, const std::string& name);

// What is wrong with the parameters for an estimator that reads `infos`
// (the key as the scene file spells it under render, and what), or
// nothing: a key it does not read (with the list of those it does), a
// number out of range, a text where a number belongs or the other way
// round, a name it does not know.
struct ParameterProblem {
    std::string key, what;
};
std::optional<ParameterProblem> checkParameters(const std::vector<ParameterInfo>& infos,
                                                const EstimatorParameters& parameters, const std::string& estimator);

}  // namespace pl
