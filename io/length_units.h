// The length unit a mesh file's coordinates are in. printlight works in
// millimetres; glTF 2.0 says its coordinates are metres, 3MF defaults to
// millimetres, OBJ, STL and PLY say nothing (3D printing takes them as
// millimetres).
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>

#include "core/enum_names.h"

namespace pl {

enum class LengthUnit { Metre, Millimetre, Inch };
inline constexpr std::array<EnumName<LengthUnit>, 3> kLengthUnitNames{
    {{LengthUnit::Metre, "m"}, {LengthUnit::Millimetre, "mm"}, {LengthUnit::Inch, "in"}}};

// "m", "mm" or "in"; none otherwise.
std::optional<LengthUnit> parseLengthUnit(const std::string& name);
const char* lengthUnitName(LengthUnit unit);
double millimetresPer(LengthUnit unit);

// What a mesh file's format says (or is taken to say) of its unit, and why.
struct FormatUnit {
    LengthUnit unit;
    const char* why;  // e.g. "glTF coordinates are metres"
};
FormatUnit formatUnitOf(const std::filesystem::path& meshFile);

// How a mesh is placed in printlight's millimetres: its file's unit (none:
// its format's) and a uniform scale after that (prepare's --fit-mm).
struct MeshPlacement {
    std::optional<LengthUnit> unit;
    double scale = 1.0;
    double millimetresPerFileUnit(const std::filesystem::path& meshFile) const {
        return millimetresPer(unit ? *unit : formatUnitOf(meshFile).unit) * scale;
    }
};

}  // namespace pl
