#include "io/printer_gamut_io.h"

#include "io/json_util.h"
#include "io/output_file.h"

namespace pl {

namespace {
constexpr const char* kFormat = "printlight-printer-gamut-1";
}

void writePrinterGamut(const PrinterGamut& gamut, const std::string& key, const std::string& settingsJson,
                       const std::filesystem::path& file) {
    nlohmann::json j;
    j["format"] = kFormat;
    j["key"] = key;
    j["levels"] = gamut.levels();
    j["settings"] = nlohmann::json::parse(settingsJson);
    nlohmann::json mixtures = nlohmann::json::array(), reflectance = nlohmann::json::array(),
                   errors = nlohmann::json::array();
    const std::vector<MaterialFractions> grid = PrinterGamut::gridMixtures(gamut.levels());
    for (size_t i = 0; i < grid.size(); ++i) {
        mixtures.push_back(grid[i]);
        reflectance.push_back(gamut.gridReflectance()[i]);
        errors.push_back(gamut.gridStandardError()[i]);
    }
    j["mixtures"] = mixtures;
    j["reflectance"] = reflectance;
    j["standard_error"] = errors;
    writeTextFile(file, j.dump(1) + "\n");
}

std::optional<PrinterGamut> readPrinterGamut(const std::filesystem::path& file, const std::string& key,
                                             std::string* keyFound) {
    if (!std::filesystem::exists(file)) return std::nullopt;
    JsonReader json(file);
    const nlohmann::json& root = json.root();
    if (!root.is_object() || json.string(root, "format", "the file", "") != kFormat)
        json.fail("format", std::string("is not a printer characterisation (") + kFormat + ")");
    const std::string fileKey = json.string(root, "key", "the file");
    if (keyFound) *keyFound = fileKey;
    if (!key.empty() && fileKey != key) return std::nullopt;
    const int64_t levels = json.integer(root, "levels", "the file");
    if (levels < 1 || levels > 64) json.fail("levels", "must be in [1, 64]");
    const size_t count = PrinterGamut::gridMixtures(int(levels)).size();
    auto triples = [&](const char* name) {
        const nlohmann::json& list = root.contains(name) ? root.at(name) : nlohmann::json();
        if (!list.is_array() || list.size() != count)
            json.fail(name, "must list one [r, g, b] per grid mixture (" + std::to_string(count) + ")");
        std::vector<RGB> out;
        for (const nlohmann::json& t : list) {
            if (!t.is_array() || t.size() != 3 || !t[0].is_number() || !t[1].is_number() || !t[2].is_number())
                json.fail(name, "must hold [r, g, b] numbers");
            out.push_back({t[0].get<float>(), t[1].get<float>(), t[2].get<float>()});
        }
        return out;
    };
    std::vector<RGB> reflectance = triples("reflectance"), errors = triples("standard_error");
    for (const RGB& r : reflectance)
        for (float x : r)
            if (!(x > 0 && x <= 1.5f)) json.fail("reflectance", "values must be in (0, 1.5]");
    return PrinterGamut(int(levels), std::move(reflectance), std::move(errors));
}

}  // namespace pl
