// Batch manifests (`printlight batch`): a list of scene renders, each with
// its own seed and sample count, for unattended and regression runs.
// Format in docs/batch.md; scene paths are relative to the manifest.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace pl {

struct BatchJob {
    std::string name;  // result file stem, unique in the manifest
    std::filesystem::path sceneFile;
    uint32_t spp = 0;
    uint64_t seed = 0;
    std::optional<std::string> integrator;         // overrides the scene's
    std::optional<std::vector<int>> channels;      // overrides the scene's
};

struct BatchManifest {
    std::filesystem::path file;
    std::vector<BatchJob> jobs;
};

// Parses and validates the manifest; reads no scene.
BatchManifest parseBatchManifest(const std::filesystem::path& file);

}  // namespace pl
