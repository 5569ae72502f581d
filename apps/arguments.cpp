#include "apps/arguments.h"

#include <algorithm>
#include <cstdlib>

#include <CLI/CLI.hpp>

namespace pl {

namespace {

std::string firstName(const std::string& names) { return names.substr(0, names.find(',')); }

}  // namespace

Arguments::Arguments(const std::string& commandName, const std::vector<std::string>& args,
                     const std::vector<Option>& options) {
    const Command& command = commandNamed(commandName);
    CLI::App app(command.summary, "printlight " + commandName);
    app.get_formatter()->column_width(34);
    std::vector<std::pair<std::string, CLI::Option*>> declared;
    std::map<std::string, std::string> given;
    for (const Option& o : options) {
        const std::string name = firstName(o.names);
        CLI::Option* opt = o.valueName.empty() ? app.add_flag(o.names, o.help)
                                               : app.add_option(o.names, given[name], o.help)->type_name(o.valueName);
        declared.emplace_back(name, opt);
    }
    if (*command.operands)
        app.add_option(command.operands, positional_, command.operandHelp)->type_name("")->expected(0, -1);
    try {
        std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 reads a vector from its end
        app.parse(reversed);
    } catch (const CLI::CallForHelp&) {
        throw HelpRequested{app.help()};
    } catch (const CLI::ParseError& e) {
        std::string what = e.what();
        std::replace(what.begin(), what.end(), '\n', ' ');
        throw UsageError(commandName + ": " + what);
    }
    for (const auto& [name, opt] : declared)
        if (opt->count() > 0) values_[name] = given[name];
}

std::optional<int64_t> Arguments::integer(const std::string& name, int64_t lo, int64_t hi) const {
    auto v = value(name);
    if (!v) return std::nullopt;
    size_t used = 0;
    int64_t x = 0;
    try {
        x = std::stoll(*v, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != v->size() || x < lo || x > hi)
        throw UsageError(name + " must be an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
    return x;
}

std::optional<double> Arguments::number(const std::string& name) const {
    auto v = value(name);
    if (!v) return std::nullopt;
    char* end = nullptr;
    const double x = std::strtod(v->c_str(), &end);
    if (v->empty() || end != v->c_str() + v->size()) throw UsageError(name + " takes a number");
    return x;
}

}  // namespace pl
