#include "io/materials_io.h"

#include "io/json_util.h"

namespace pl {

MaterialTable loadMaterials(const std::filesystem::path& file) {
    JsonReader json(file);
    return readMaterials(json, json.root());
}

MaterialTable readMaterials(const JsonReader& json, const nlohmann::json& node) {
    const nlohmann::json* list = &node;
    // Accept a bare list or {"materials": [...]}.
    if (list->is_object()) {
        json.expectOnlyKeys(*list, "", {"materials", "comment"});
        if (!list->contains("materials")) json.fail("materials", "is missing");
        list = &(*list)["materials"];
    }
    if (!list->is_array()) json.fail("", "must be a list of materials");
    if (list->empty()) json.fail("", "holds no materials");

    MaterialTable table;
    for (size_t i = 0; i < list->size(); ++i) {
        const nlohmann::json& m = (*list)[i];
        std::string where = "materials[" + std::to_string(i) + "]";
        if (!m.is_object()) json.fail(where, "must be an object");
        json.expectOnlyKeys(m, where, {"label", "name", "albedo", "density", "anisotropy", "ior", "comment"});
        int64_t label = json.integer(m, "label", where);
        if (label < 0 || label > 255) json.fail(where + ".label", "must be in 0..255");
        Material& mat = table.byLabel[size_t(label)];
        if (mat.defined) json.fail(where + ".label", "repeats label " + std::to_string(label));
        mat.name = json.string(m, "name", where, "label" + std::to_string(label));
        mat.albedo = json.rgb(m, "albedo", where);
        mat.sigmaT_perMm = json.rgb(m, "density", where);
        mat.g = m.contains("anisotropy") ? json.rgb(m, "anisotropy", where) : RGB{0, 0, 0};
        for (int c = 0; c < 3; ++c) {
            if (mat.sigmaT_perMm[c] < 0) json.fail(where + ".density", "must not be negative");
            if (mat.albedo[c] < 0 || mat.albedo[c] > 1) json.fail(where + ".albedo", "must be in [0, 1]");
            if (!(std::abs(mat.g[c]) < 1)) json.fail(where + ".anisotropy", "must satisfy |g| < 1");
        }
        if (m.contains("ior") && !(json.number(m, "ior", where) > 0))
            json.fail(where + ".ior", "must be positive");
        mat.defined = true;
    }
    return table;
}

}  // namespace pl
