// Scene JSON (documented key by key in docs/scene-format.md). Input paths
// are relative to the scene file; the output path to the working directory.
#pragma once

#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "core/enum_names.h"
#include "core/sensors.h"
#include "io/length_units.h"
#include "render/render.h"
#include "scene/scene.h"

namespace pl {

struct SensorDescription {
    std::string type = "surface_voxels";  // surface_voxels | perspective | orthographic
    // surface_voxels: what a voxel's value measures (core/sensors.h).
    SurfaceVoxelSensor::Footprint footprint = SurfaceVoxelSensor::Footprint::Ray;
    CameraPose pose;
    float fovY_deg = 30.0f;
    float viewWidth_mm = 10.0f;
    int width = 0, height = 0;
};

struct SceneDescription {
    std::filesystem::path sceneFile;
    std::filesystem::path meshFile, labelsFile, materialsFile;
    MeshPlacement meshPlacement;  // the mesh file's unit and scale
    bool meshRepair = false;      // repair the mesh as it loads (io/mesh_repair.h)
    std::optional<Label> voidLabel;
    float ior = 1.5f;
    // > 0: voxels deeper than this take the core's one label (scene/homogeneous_core.h).
    float homogeneousCoreDepth_mm = 0;
    RGB environment{1, 1, 1};
    SensorDescription sensor;
    RenderSettings render;
    std::filesystem::path output;  // without extension

    std::vector<std::filesystem::path> inputFiles() const {
        return {sceneFile, meshFile, labelsFile, materialsFile};
    }
};

// Parses and validates the JSON; reads no other file.
SceneDescription parseScene(const std::filesystem::path& sceneFile);

// Writes the scene file parseScene reads back as `desc`: input paths
// relative to the file's folder, the render block's keys only where they
// differ from the defaults (each from its option or name table).
void writeScene(const SceneDescription& desc, const std::filesystem::path& file);

// Loads mesh, label grid and materials and checks they fit together, plus
// what `needs` asks for.
Scene loadScene(const SceneDescription& desc, SceneNeeds needs = {});

// Builds the sensor (for surface_voxels this enumerates the surface voxels);
// refuses one whose pixels would not fit in memory.
std::unique_ptr<Sensor> makeSensor(const SceneDescription& desc, const Scene& scene);
// The surface_voxels sensor over given surface voxels of the scene's grid,
// with the same checks (the prediction API keeps the voxels it computed).
std::unique_ptr<SurfaceVoxelSensor> makeSurfaceVoxelSensor(const SceneDescription& desc, const Scene& scene,
                                                           const std::vector<SurfaceVoxel>& surfaceVoxels);

// Parses "r", "g", "b" or "rgb".
std::optional<std::vector<int>> parseChannels(const std::string& s);
// The inverse: {0, 1, 2} -> "rgb", {1} -> "g".
std::string channelNames(const std::vector<int>& channels);
// "separate", "hero" or "spectral" (nullopt otherwise), and back.
inline constexpr std::array<EnumName<ChannelSampling>, 3> kChannelSamplingNames{
    {{ChannelSampling::Separate, "separate"}, {ChannelSampling::Hero, "hero"}, {ChannelSampling::Spectral, "spectral"}}};
std::optional<ChannelSampling> parseChannelSampling(const std::string& s);
const char* channelSamplingName(ChannelSampling s);

}  // namespace pl
