// The printer characterised by printlight itself: each mixture of the
// mixing simplex's grid halftoned into the outer shell of a cube over a
// white core, as prepare prints a colour, and rendered converged; the
// colour is the mean reflectance over the centres of the cube's six faces,
// far from its edges (prepare/printer_gamut.h interpolates between the
// mixtures). Made once per material table and kept in a file
// (io/printer_gamut_io.h) whose key is the table's contents and these
// settings.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "core/vecmath.h"
#include "media/materials.h"
#include "prepare/printer_gamut.h"

namespace pl {

struct CharacterisationSettings {
    int levels = 8;                                 // grid step 1/levels on the mixing simplex
    Vec3f voxel_mm = kPrinterVoxel_mm;      // the printer's voxel
    float shellDepth_mm = 1.0f;                     // as prepare and optimize colour the object
    float cube_mm = 6.0f;
    float measuredSquare_mm = 2.0f;                 // the centre of each face that is measured
    std::string integrator = "volpath";
    uint32_t spp = 8;
    uint64_t seed = 1;
    float ior = 1.5f;
};

// What the characterisation's colours depend on: the materials and the
// settings (and a format version), as 16 hexadecimal digits.
std::string characterisationKey(const MaterialTable& materials, const CharacterisationSettings& settings);

// Renders every grid mixture; with showProgress, a progress bar on stderr
// (when it is a terminal).
PrinterGamut characterisePrinter(const MaterialTable& materials, const CharacterisationSettings& settings,
                                 bool showProgress = false);

// Writes the characterisation with its key (io/printer_gamut_io.h).
void writeCharacterisation(const PrinterGamut& gamut, const MaterialTable& materials,
                           const CharacterisationSettings& settings, const std::filesystem::path& file);

// The characterisation of a material table: the file beside it
// (MATERIALS.gamut.json) or in the user's cache ($XDG_CACHE_HOME or
// ~/.cache, printlight/KEY.gamut.json) if its key matches; otherwise made
// (with a progress bar on a terminal) and written to the cache. `said`
// receives one line saying which.
PrinterGamut printerGamutFor(const std::filesystem::path& materialsFile, const CharacterisationSettings& settings,
                             const std::function<void(const std::string&)>& said = {});

// A characterisation file the user names (throws InputError if it is
// missing or malformed); `said` notes it if it was made for other
// materials or settings than these.
PrinterGamut readPrinterGamutFile(const std::filesystem::path& file, const std::filesystem::path& materialsFile,
                                  const CharacterisationSettings& settings,
                                  const std::function<void(const std::string&)>& said = {});

}  // namespace pl
