// The printer characterisation's file (JSON; api/printer_characterisation.h):
//   {"format": "printlight-printer-gamut-1", "key": "<16 hex digits>",
//    "levels": n, "settings": {...what the key covers, for people...},
//    "mixtures": [[c, m, y, k, w], ...] (PrinterGamut::gridMixtures order),
//    "reflectance": [[r, g, b], ...], "standard_error": [[r, g, b], ...]}
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "prepare/printer_gamut.h"

namespace pl {

void writePrinterGamut(const PrinterGamut& gamut, const std::string& key, const std::string& settingsJson,
                       const std::filesystem::path& file);

// The gamut in `file` if it exists and was made under `key` (any key if
// empty; nothing otherwise); throws InputError if the file is malformed.
// keyFound: the file's key.
std::optional<PrinterGamut> readPrinterGamut(const std::filesystem::path& file, const std::string& key,
                                             std::string* keyFound = nullptr);

}  // namespace pl
