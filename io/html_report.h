// A self-contained HTML report: models (glTF binaries, e.g. a prediction,
// its target and the per-voxel error) on rotating views side by side, and
// a value per iteration of an optimisation run as a plot. The viewer is
// three.js, bundled from npm at build time (web/) and inlined with the
// models, so the page needs no network when it is viewed.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace pl {

struct HtmlReport {
    std::string title;
    std::string summary;  // a line under the title
    struct Model {
        std::string label;
        std::filesystem::path glb;
    };
    std::vector<Model> models;
    struct Point {
        double iteration, value;
    };
    std::vector<Point> history;  // empty: no plot
    std::string historyLabel;
};

void writeHtmlReport(const HtmlReport& report, const std::filesystem::path& file);

}  // namespace pl
