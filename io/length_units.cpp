#include "io/length_units.h"

#include "io/file_names.h"

namespace pl {

std::optional<LengthUnit> parseLengthUnit(const std::string& name) { return parseEnum(kLengthUnitNames, name); }

const char* lengthUnitName(LengthUnit unit) { return enumName(kLengthUnitNames, unit); }

double millimetresPer(LengthUnit unit) {
    switch (unit) {
        case LengthUnit::Metre: return 1000.0;
        case LengthUnit::Millimetre: return 1.0;
        case LengthUnit::Inch: return 25.4;
    }
    return 1.0;
}

FormatUnit formatUnitOf(const std::filesystem::path& meshFile) {
    const std::string ext = lowerExtension(meshFile);
    if (ext == ".gltf" || ext == ".glb") return {LengthUnit::Metre, "glTF coordinates are metres"};
    if (ext == ".3mf") return {LengthUnit::Millimetre, "3MF's default unit (the file's unit attribute is not read)"};
    return {LengthUnit::Millimetre, "the format has no unit; taken as millimetres"};
}

}  // namespace pl
