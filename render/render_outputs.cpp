#include "render/render_outputs.h"

#include <cstdio>

#include "io/grid_io.h"
#include "io/mesh_io.h"

namespace pl {

RenderOutputs::RenderOutputs(const std::filesystem::path& output, const SensorDescription& sensor)
    : base_(output), surface_(sensor.type == "surface_voxels") {
    const std::string ext = base_.extension().string();
    if (ext == ".exr" || ext == ".png" || ext == ".vdb" || ext == ".glb") base_.replace_extension();
}

std::vector<std::filesystem::path> RenderOutputs::files() const {
    std::vector<std::filesystem::path> files = {base_.string() + ".exr", base_.string() + ".png"};
    if (surface_) {
        files.push_back(base_.string() + ".vdb");
        files.push_back(base_.string() + ".glb");
    }
    return files;
}

void RenderOutputs::writeImage(const RadianceImage& image) const {
    writeExr(image, base_.string() + ".exr");
    writePng(image, base_.string() + ".png");
}

void RenderOutputs::writeSurface(const TriangleMesh& mesh_mm, const GridFrame& worldFrame,
                                 const std::vector<Vec3i>& voxels, PixelResults results) {
    writeSurfaceResultVdb(worldFrame, voxels, results, base_.string() + ".vdb");
    results.standardError = {};
    try {
        writePredictionGlb(mesh_mm, worldFrame, voxels, results.mean, base_.string() + ".glb");
        glbWritten_ = true;
    } catch (const GlbTooLarge& e) {
        std::fprintf(stderr, "printlight: warning: %s\n", e.what());
    }
}

std::string RenderOutputs::writtenText() const {
    return base_.string() + (glbWritten_ ? ".{exr,png,vdb,glb}" : surface_ ? ".{exr,png,vdb}" : ".{exr,png}");
}

std::vector<std::pair<std::string, std::string>> renderMetadata(const SceneDescription& desc, uint32_t spp) {
    return {{"scene", desc.sceneFile.string()},
            {"integrator", desc.render.integrator},
            {"sensor", desc.sensor.type},
            {"spp", std::to_string(spp)},
            {"seed", std::to_string(desc.render.seed)},
            {"channels", channelNames(desc.render.channels)},
            {"channel_sampling", channelSamplingName(desc.render.channelSampling)}};
}

}  // namespace pl
