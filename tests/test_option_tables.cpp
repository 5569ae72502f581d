// Options declared once (core/option_table.h): every key of the render
// block's own table and of each registered estimator's is one render key
// of the scene file, has its row in docs/scene-format.md, takes its own
// default without complaint, and refuses a value out of its range with
// its text.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <variant>

#include "integrators/render_settings.h"
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
    std::set<std::string> renderNames;
    expectDeclaredOnceAndDocumented(renderParameters(), renderNames, doc);
    // Every estimator's keys, found through the registry: documented, and
    // out of range refused by the driver's check with the key's own text.
    std::map<std::string, std::string> docOf;
    for (const IntegratorKind& kind : integratorKinds()) {
        for (const ParameterInfo& p : kind.factory.parameters()) {
            EXPECT_EQ(renderNames.count(p.name), 0u) << p.name << " is also the render block's own";
            EXPECT_NE(doc.find("| `" + p.name + "` |"), std::string::npos) << p.name << " undocumented";
            EXPECT_GT(p.doc.size(), 10u) << p.name;
            // A key shared by estimators is one declaration (the same table).
            auto [it, first] = docOf.emplace(p.name, p.doc);
            EXPECT_TRUE(first || it->second == p.doc) << p.name << " declared twice";
            auto refusal = [&](auto set) {
                EstimatorParameters params;
                set(params);
                auto problem = checkParameters(kind.factory.parameters(), params, kind.name);
                return problem ? problem->key + ": " + problem->what : std::string();
            };
            using Kind = ParameterInfo::Kind;
            const std::string refused = p.name + ": " + p.rangeText;
            if (p.kind == Kind::Integer || p.kind == Kind::Number) {
                EXPECT_EQ(refusal([&](EstimatorParameters& e) { e.set(p.name, p.max * 2 + 1); }), refused);
                EXPECT_EQ(refusal([&](EstimatorParameters& e) { e.set(p.name, p.min - 1); }), refused);
                EXPECT_EQ(refusal([&](EstimatorParameters& e) { e.set(p.name, p.max); }), "");
            }
            if (p.kind == Kind::Integer) {
                EXPECT_EQ(refusal([&](EstimatorParameters& e) { e.set(p.name, 0.5); }), refused);
            }
            if (p.kind == Kind::Name) {
                EXPECT_EQ(refusal([&](EstimatorParameters& e) { e.setText(p.name, "no_such_name"); }), refused);
                for (const std::string& n : p.names)
                    EXPECT_EQ(refusal([&](EstimatorParameters& e) { e.setText(p.name, n); }), "");
            }
            if (p.isText()) {
                EXPECT_NE(refusal([&](EstimatorParameters& e) { e.set(p.name, 1); }), "") << p.name;
            }
        }
        // A key the estimator does not read is refused with the list of those it does.
        EstimatorParameters misspelt;
        misspelt.set("no_such_option", 1);
        auto problem = checkParameters(kind.factory.parameters(), misspelt, kind.name);
        ASSERT_TRUE(problem) << kind.name;
        EXPECT_EQ(problem->key, "no_such_option");
        for (const ParameterInfo& p : kind.factory.parameters())
            EXPECT_NE(problem->what.find(p.name), std::string::npos) << kind.name << ": " << problem->what;
    }
    // Every estimator with options is seen.
    for (const char* name : {"max_depth", "branches", "particles_per_pixel", "lighttrace_scoring", "learned_model",
                             "bre_alpha", "beams_alpha"})
        EXPECT_EQ(docOf.count(name), 1u) << name;
}

// Another estimator named for the same settings keeps the keys it reads
// and drops the others' (a lighttrace scene rendered by volpath).
TEST(OptionTables, AnotherEstimatorKeepsOnlyItsOwnKeys) {
    RenderSettings s;
    s.integrator = "lighttrace";
    s.parameters.set("particles_per_pixel", 4);
    s.parameters.set("max_depth", 5);
    s.parameters.setText("lighttrace_scoring", "collisions");
    EXPECT_EQ(refusalOf(s), "");
    RenderSettings v = s;
    v.integrator = "volpath";
    EXPECT_EQ(refusalOf(v), "render.particles_per_pixel: not an option of volpath (its options: max_depth, clearance_first)");
    setIntegrator(v, "volpath");
    EXPECT_EQ(refusalOf(v), "");
    EXPECT_EQ(v.parameters.numbers().size(), 1u);
    ASSERT_TRUE(v.parameters.number("max_depth"));
    EXPECT_EQ(*v.parameters.number("max_depth"), 5.0);
    EXPECT_TRUE(v.parameters.texts().empty());
}

// The architecture's diagram names every registered estimator on its
// "estimators:" line (docs/architecture.md, "Data flow").
TEST(Docs, ArchitectureDiagramNamesEveryEstimator) {
    const std::string doc = test::readText(test::sourceDir() / "docs/architecture.md");
    const size_t at = doc.find("\nestimators:");
    ASSERT_NE(at, std::string::npos) << "no 'estimators:' line in docs/architecture.md";
    const std::string line = doc.substr(at + 1, doc.find('\n', at + 1) - at - 1) + " ";
    for (const IntegratorKind& kind : integratorKinds()) {
        if (std::string(kind.name) == "surface_reflection") continue;  // the example a test registers
        EXPECT_NE(line.find(std::string(" ") + kind.name + " "), std::string::npos) << kind.name << " not in: " << line;
    }
}

}  // namespace
}  // namespace pl
