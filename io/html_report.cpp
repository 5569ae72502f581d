#include "io/html_report.h"

#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>

#include "io/base64.h"
#include "core/input_error.h"
#include "io/output_file.h"

namespace pl {

const char* reportViewerScript();  // generated at build time (cmake/embed_text.cmake)

namespace {

std::string readBytes(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(file.string(), "cannot open file");
    return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

void writeHtmlReport(const HtmlReport& report, const std::filesystem::path& file) {
    nlohmann::json data = {{"title", report.title}, {"summary", report.summary}, {"historyLabel", report.historyLabel}};
    data["models"] = nlohmann::json::array();
    for (const auto& m : report.models) {
        const std::string bytes = readBytes(m.glb);
        if (bytes.size() < 12 || bytes.compare(0, 4, "glTF") != 0)
            throw InputError(m.glb.string(), "not a glTF binary (.glb)");
        data["models"].push_back({{"label", m.label}, {"glb", base64(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size())}});
    }
    data["history"] = nlohmann::json::array();
    for (const auto& p : report.history) data["history"].push_back({{"iteration", p.iteration}, {"value", p.value}});
    // "</" cannot end the script elements early: JSON may escape the slash.
    std::string json = data.dump();
    for (size_t at = json.find("</"); at != std::string::npos; at = json.find("</", at + 3)) json.replace(at, 2, "<\\/");
    std::string script = reportViewerScript();
    for (size_t at = script.find("</script"); at != std::string::npos; at = script.find("</script", at + 9))
        script.replace(at, 8, "<\\/script");

    std::string html =
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>printlight report</title>\n"
        "<style>body{font-family:sans-serif;margin:1em;background:#f4f4f4}#views{display:flex;flex-wrap:wrap;gap:1em}"
        "figure{margin:0}canvas{width:360px;height:360px;display:block;border:1px solid #aaa}"
        "figcaption{text-align:center;margin-top:.3em}</style>\n</head>\n<body>\n"
        "<h1 id=\"title\"></h1>\n<p id=\"summary\"></p>\n<div id=\"views\"></div>\n<div id=\"history\"></div>\n"
        "<script type=\"application/json\" id=\"printlight-data\">" + json + "</script>\n<script>" + script +
        "</script>\n</body>\n</html>\n";
    writeTextFile(file, html);
}

}  // namespace pl
