// Fuzz target: material tables.
#include "core/input_error.h"
#include "io/materials_io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    auto file = pl::fuzz::writeInput(data, size, ".json");
    try {
        pl::loadMaterials(file);
    } catch (const pl::InputError&) {
    }
    return 0;
}
