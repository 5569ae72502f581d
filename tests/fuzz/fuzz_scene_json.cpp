// Fuzz target: scene JSON (parseScene) and batch manifests, which share the
// JSON reader.
#include "render/batch_manifest.h"
#include "core/input_error.h"
#include "render/scene_io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    auto file = pl::fuzz::writeInput(data, size, ".json");
    try {
        pl::parseScene(file);
    } catch (const pl::InputError&) {
    }
    try {
        pl::parseBatchManifest(file);
    } catch (const pl::InputError&) {
    }
    return 0;
}
