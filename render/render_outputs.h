// What a render writes, chosen from its sensor in one place:
//  - every sensor: OUT.exr (mean, standard error and coverage per image
//    pixel, with how it was made in its header) and OUT.png (the preview);
//  - a surface-voxel sensor also: OUT.vdb (per-voxel radiance and standard
//    error grids in the label grid's transform) and OUT.glb (the prediction
//    on the model).
// Batch results are the film in sensor-pixel order instead
// (io/image_io.h, filmToPixelImage), a regression format.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "io/image_io.h"
#include "render/scene_io.h"

namespace pl {

class RenderOutputs {
public:
    // output: the path without extension (a known one is dropped).
    RenderOutputs(const std::filesystem::path& output, const SensorDescription& sensor);
    bool surface() const { return surface_; }
    // Every file it writes, to check against the inputs before a render.
    std::vector<std::filesystem::path> files() const;
    // The image and its preview (after each round of a progressive render
    // too; each write complete: io/output_file.h).
    void writeImage(const RadianceImage& image) const;
    // The surface voxels' results (a surface-voxel sensor): the result grid,
    // then the prediction on the model, which is left out with a warning
    // when it would pass the glTF format's 4 GiB.
    void writeSurface(const TriangleMesh& mesh_mm, const GridFrame& worldFrame, const std::vector<Vec3i>& voxels,
                      PixelResults results);
    // "OUT.{exr,png,vdb,glb}": what was written.
    std::string writtenText() const;

private:
    std::filesystem::path base_;
    bool surface_ = false, glbWritten_ = false;
};

// How the image was made, for its header: scene, integrator, sensor, spp,
// seed, channels and their sampling.
std::vector<std::pair<std::string, std::string>> renderMetadata(const SceneDescription& desc, uint32_t spp);

}  // namespace pl
