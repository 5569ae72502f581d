// Options declared once: each by its scene-file name, the field of its
// options struct it sets, its range and what it does. The scene parser,
// bench's "estimator/key=value" configurations and the tests read the
// same table (integrators/printpt/printpt_options.h, lighttrace.h, volpath.h).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace pl {

// Booleans take any value (non-zero: on); integer fields whole numbers
// only (as doubles: exact up to 2^53).
template <class Options>
struct OptionParameter {
    const char* name;
    std::variant<bool Options::*, int Options::*, int64_t Options::*, uint32_t Options::*, uint64_t Options::*,
                 float Options::*, double Options::*>
        field;
    double min = 0, max = 0;
    bool minOpen = false;   // (min, max] instead of [min, max]
    const char* rangeText;  // what a value out of range is told ("must be ...")
    const char* doc;
    enum class Kind { Boolean, Integer, Number };
    Kind kind() const {
        if (std::holds_alternative<bool Options::*>(field)) return Kind::Boolean;
        if (std::holds_alternative<float Options::*>(field) || std::holds_alternative<double Options::*>(field))
            return Kind::Number;
        return Kind::Integer;
    }
};

// The table's option of that name, or none.
template <class Options>
const OptionParameter<Options>* findOption(const std::vector<OptionParameter<Options>>& table,
                                           const std::string& name) {
    for (const OptionParameter<Options>& p : table)
        if (name == p.name) return &p;
    return nullptr;
}

// Whether a number lies in [min, max] ((min, max] with minOpen), and is
// whole if asked. A float field's value is checked as the field will hold it.
inline bool inOptionRange(double value, double min, double max, bool minOpen, bool whole, bool singlePrecision) {
    if (singlePrecision) value = double(float(value));
    const bool inRange = (minOpen ? value > min : value >= min) && value <= max;
    return inRange && (!whole || value == double(int64_t(value)));
}

// Sets the option (booleans: value != 0). Returns what is wrong with the
// value ("must be in (0, 1]"), or "" if it was set.
template <class Options>
std::string setOption(const OptionParameter<Options>& p, Options& options, double value) {
    using Kind = typename OptionParameter<Options>::Kind;
    if (auto flag = std::get_if<bool Options::*>(&p.field)) {
        options.*(*flag) = value != 0.0;
        return "";
    }
    if (!inOptionRange(value, p.min, p.max, p.minOpen, p.kind() == Kind::Integer,
                       std::holds_alternative<float Options::*>(p.field)))
        return p.rangeText;
    std::visit(
        [&](auto member) {
            using Field = std::remove_reference_t<decltype(options.*member)>;
            options.*member = Field(value);
        },
        p.field);
    return "";
}

// The option's value in `options` (booleans: 0 or 1).
template <class Options>
double optionValue(const OptionParameter<Options>& p, const Options& options) {
    return std::visit([&](auto member) { return double(options.*member); }, p.field);
}

// The same by name; throws std::invalid_argument for a name the table
// does not hold.
template <class Options>
std::string setOption(const std::vector<OptionParameter<Options>>& table, Options& options, const std::string& name,
                      double value) {
    const OptionParameter<Options>* p = findOption(table, name);
    if (!p) throw std::invalid_argument("unknown option '" + name + "'");
    return setOption(*p, options, value);
}

}  // namespace pl
