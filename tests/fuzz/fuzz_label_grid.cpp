// Fuzz target: the LabelGrid .bin and Mitsuba .vol readers (the first byte
// picks the format; the rest is the file). A grid that loads is also asked
// for its surface voxels and histogram, which walk the whole tree.
#include "io/grid_io.h"
#include "core/input_error.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    auto file = pl::fuzz::writeInput(data + 1, size - 1, (data[0] & 1) ? ".vol" : ".bin");
    try {
        pl::LabelGrid grid = pl::loadLabelGrid(file, std::nullopt);
        (void)grid.histogram();
        (void)grid.surfaceVoxels();
    } catch (const pl::InputError&) {
    }
    return 0;
}
