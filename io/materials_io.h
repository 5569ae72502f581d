// Materials JSON: a list of {"label", "name", "albedo": [r,g,b],
// "density": [r,g,b] (sigma_t, 1/mm), "anisotropy": [r,g,b] (HG g)},
// optionally "ior"; the format of the public research code of Rittig et
// al. 2021. See docs/formats.md, "Materials JSON".
#pragma once

#include <filesystem>

#include "io/json_util.h"
#include "media/materials.h"

namespace pl {

MaterialTable loadMaterials(const std::filesystem::path& file);

// The bundled material table and its printer characterisation, compiled in
// (for models prepared without a table of their own).
constexpr const char* kBundledMaterialName = "data/materials/resins_illustrative.json";
const char* bundledMaterialTable();
const char* bundledPrinterGamut();  // data/materials/resins_illustrative.gamut.json
// The same from a node of a JSON file (a list, or {"materials": [...]}).
MaterialTable readMaterials(const JsonReader& json, const nlohmann::json& node);

}  // namespace pl
