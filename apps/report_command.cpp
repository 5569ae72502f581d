// printlight report: glTF binaries (a prediction, its target, an error map)
// and an optional per-iteration history -> one self-contained HTML page.

#include <fstream>
#include <sstream>

#include "apps/arguments.h"
#include "apps/command_options.h"
#include "io/html_report.h"
#include "core/input_error.h"
#include "io/output_file.h"

namespace pl {

namespace {

// The named column of a CSV file with a header line (optimize's PREFIX.csv),
// against its first column.
std::vector<HtmlReport::Point> readHistory(const std::filesystem::path& file, const std::string& column) {
    std::ifstream in(file);
    if (!in) throw InputError(file.string(), "cannot open file");
    std::string line;
    if (!std::getline(in, line)) throw InputError(file.string(), "empty file");
    const std::vector<std::string> header = splitList(line);
    size_t at = 0;
    while (at < header.size() && header[at] != column) ++at;
    if (at == header.size()) throw InputError(file.string(), "no column '" + column + "'");
    std::vector<HtmlReport::Point> points;
    for (int row = 2; std::getline(in, line); ++row) {
        const std::vector<std::string> cells = splitList(line);
        try {
            if (cells.size() != header.size()) throw std::invalid_argument("");
            points.push_back({std::stod(cells[0]), std::stod(cells[at])});
        } catch (const std::exception&) {
            throw InputError(file.string(), "line " + std::to_string(row) + ": not a row of numbers");
        }
    }
    return points;
}

}  // namespace

int reportCommand(const std::vector<std::string>& argv) {
    Arguments args("report", argv,
                   {{"-o,--output", "REPORT.html", "the page (required)"},
                    {"--labels", "A,B,...", "a caption per model (default: the file names)"},
                    {"--title", "TEXT", "the page's title"},
                    {"--summary", "TEXT", "a line under the title"},
                    {"--history", "FILE.csv", "a per-iteration plot from a CSV (optimize's PREFIX.csv)"},
                    {"--history-column", "NAME", "the CSV column to plot (default mean_de2000)"}});
    if (args.positional().empty()) throw UsageError("report needs at least one MODEL.glb");
    auto output = args.value("-o");
    if (!output) throw UsageError("report needs -o REPORT.html");
    HtmlReport report;
    report.title = args.value("--title").value_or("printlight prediction");
    report.summary = args.value("--summary").value_or("");
    std::vector<std::string> labels = splitList(args.value("--labels").value_or(""));
    if (args.has("--labels") && labels.size() != args.positional().size())
        throw UsageError("--labels needs one caption per model");
    std::vector<std::filesystem::path> inputs;
    for (size_t i = 0; i < args.positional().size(); ++i) {
        const std::filesystem::path glb = args.positional()[i];
        inputs.push_back(glb);
        report.models.push_back({args.has("--labels") ? labels[i] : glb.filename().string(), glb});
    }
    if (auto h = args.value("--history")) {
        inputs.push_back(*h);
        report.historyLabel = args.value("--history-column").value_or("mean_de2000");
        report.history = readHistory(*h, report.historyLabel);
    }
    refuseToOverwriteInputs(*output, inputs);
    writeHtmlReport(report, *output);
    std::printf("report: %zu model(s)%s -> %s\n", report.models.size(), report.history.empty() ? "" : " and a history",
                output->c_str());
    return 0;
}

}  // namespace pl
