// Options declared once (core/option_table.h): every key of the render
// block's own, volpath's, lighttrace's and printpt's tables is one render key of the scene file,
// has its row in docs/scene-format.md, takes its own default without
// complaint, and refuses a value out of its range with its text.
#include <gtest/gtest.h>

#include <set>
#include <stdexcept>
#include <string>
#include <variant>

#include "integrators/lighttrace/lighttrace.h"
#include "integrators/printpt/printpt_options.h"
#include "integrators/render_settings.h"
#include "integrators/volpath/volpath.h"
#include "render/registry.h"
#include "test_util.h"

namespace pl {
namespace {

template <class Options>
void expectDeclaredOnceAndDocumented(const std::vector<OptionParameter<Options>>& table, std::set<std::string>& names,
                                     const std::string& doc) {
    using Kind = typename OptionParameter<Options>::Kind;
    for (const OptionParameter<Options>& p : table) {
        EXPECT_TRUE(names.insert(p.name).second) << p.name << " declared twice";
        EXPECT_NE(doc.find(std::string("| `") + p.name + "` |"), std::string::npos) << p.name << " undocumented";
        EXPECT_GT(std::string(p.doc).size(), 10u) << p.name;
        Options options;
        const double byDefault = optionValue(p, options);
        EXPECT_EQ(setOption(table, options, p.name, byDefault), "") << p.name;
        if (p.kind() != Kind::Boolean) {
            EXPECT_EQ(setOption(table, options, p.name, p.max * 2 + 1), p.rangeText) << p.name;
            EXPECT_EQ(setOption(table, options, p.name, p.min - 1), p.rangeText) << p.name;
        }
        if (p.kind() == Kind::Integer) {
            EXPECT_EQ(setOption(table, options, p.name, 0.5), p.rangeText) << p.name;
        }
    }
    Options options;
    EXPECT_THROW(setOption(table, options, "no_such_option", 1), std::invalid_argument);
}

TEST(OptionTables, EveryOptionIsDeclaredOnceAndDocumented) {
    const std::string doc = test::readText(test::sourceDir() / "docs/scene-format.md");
    std::set<std::string> names;
    expectDeclaredOnceAndDocumented(renderParameters(), names, doc);
    expectDeclaredOnceAndDocumented(volPathParameters(), names, doc);
    expectDeclaredOnceAndDocumented(lightTraceParameters(), names, doc);
    expectDeclaredOnceAndDocumented(printPtParameters(), names, doc);
    expectDeclaredOnceAndDocumented(breParameters(), names, doc);
    expectDeclaredOnceAndDocumented(beamParameters(), names, doc);
    // One render block: no key in two tables.
    EXPECT_EQ(names.size(), renderParameters().size() + volPathParameters().size() + lightTraceParameters().size() +
                                printPtParameters().size() + breParameters().size() +
                                beamParameters().size());
}

// The architecture's diagram names every registered estimator on its
// "estimators:" line (docs/architecture.md, "Data flow").
TEST(Docs, ArchitectureDiagramNamesEveryEstimator) {
    const std::string doc = test::readText(test::sourceDir() / "docs/architecture.md");
    const size_t at = doc.find("\nestimators:");
    ASSERT_NE(at, std::string::npos) << "no 'estimators:' line in docs/architecture.md";
    const std::string line = doc.substr(at + 1, doc.find('\n', at + 1) - at - 1) + " ";
    for (const IntegratorKind& kind : integratorKinds())
        if (std::string(kind.name) != "surface_reflection")  // the example a test registers
            EXPECT_NE(line.find(std::string(" ") + kind.name + " "), std::string::npos) << kind.name << " not in: " << line;
}

}  // namespace
}  // namespace pl
