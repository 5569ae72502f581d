// printlight learned-data SCENE.json --reference REF.exr -o OUT.npy: the
// learned predictor's training rows from a render of a surface-voxel
// sensor with patches (scripts/train_learned.py). One row per surface
// voxel the render's atlas shows and channel: the descriptor
// (integrators/learned/label_descriptor.h), then the voxel's response (the
// radiance along the normal less its Fresnel reflection of the
// surroundings, over the light transmitted in) and that value's standard
// error, then the channel and the element. A NumPy .npy of float32.

#include <cstdio>
#include <fstream>

#include "apps/arguments.h"
#include "apps/command_options.h"
#include "core/fresnel.h"
#include "integrators/learned/learned.h"
#include "io/image_io.h"
#include "core/input_error.h"
#include "io/output_file.h"
#include "runtime/scheduler.h"
#include "render/scene_io.h"

namespace pl {

namespace {
constexpr size_t kColumns = LabelDescriptor::kSize + 4;

void writeNpy(const std::filesystem::path& file, const std::vector<float>& rows) {
    OutputFile output(file);
    std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + std::to_string(rows.size() / kColumns) +
                         ", " + std::to_string(kColumns) + "), }";
    header.append(63 - (10 + header.size()) % 64, ' ');  // the data starts on a 64-byte boundary
    header += '\n';
    std::ofstream out(output.tempPath(), std::ios::binary);
    out.write("\x93NUMPY\x01\x00", 8);
    const uint16_t length = uint16_t(header.size());
    out.put(char(length & 0xff));
    out.put(char(length >> 8));
    out << header;
    out.write(reinterpret_cast<const char*>(rows.data()), std::streamsize(rows.size() * sizeof(float)));
    out.close();
    if (!out) throw InputError(file.string(), "cannot write");
    output.commit();
}
}  // namespace

int learnedDataCommand(const std::vector<std::string>& argv) {
    Arguments args("learned-data", argv,
                   {{"--reference", "REF.exr", "a render of the scene's surface-voxel sensor"},
                    {"-o", "OUT.npy", "the rows"},
                    kThreadsOption});
    if (args.positional().size() != 1) throw UsageError("learned-data needs exactly one SCENE.json");
    const auto referenceFile = args.value("--reference");
    const auto outFile = args.value("-o");
    if (!referenceFile || !outFile) throw UsageError("learned-data needs --reference REF.exr and -o OUT.npy");
    ThreadLimit threadLimit(args);
    const SceneDescription desc = parseScene(args.positional()[0]);
    refuseToOverwriteInputs(*outFile, {desc.sceneFile, desc.meshFile, desc.labelsFile, desc.materialsFile, *referenceFile});
    const Scene scene = loadScene(desc);
    const std::unique_ptr<Sensor> sensor = makeSensor(desc, scene);
    const auto* surface = dynamic_cast<const SurfaceVoxelSensor*>(sensor.get());
    if (!surface || !surface->patches() || surface->pixelCount() != scene.medium->grid().surfaceVoxels().size())
        throw InputError(desc.sceneFile.string(), "learned-data needs a surface_voxels sensor with \"footprint\": \"patch\"");
    const RadianceImage reference = readExr(*referenceFile);
    if (reference.mean.size() != size_t(surface->imageWidth()) * size_t(surface->imageHeight()))
        throw InputError(*referenceFile, "is not a render of this scene's surface-voxel sensor");

    const LabelDescriptor descriptor(*scene.medium, LabelDescriptor::kMostPyramidBytes);
    const size_t n = surface->pixelCount();
    std::vector<float> descriptors(n * 3 * LabelDescriptor::kSize);
    parallelForTiles(n, 256, [&](size_t begin, size_t end) {
        LabelMedium::Tracker sampler(*scene.medium);
        describeSurface(descriptor, *surface, begin, end, sampler, &descriptors[begin * 3 * LabelDescriptor::kSize]);
    });
    // Along the normal the surroundings' reflection is F(0) Le; the rest
    // is (1 - F(0)) Le x response (integrators/surface_response.h).
    const float fresnel = fresnelDielectric(1.0f, scene.ior);
    std::vector<float> rows;
    rows.reserve(n * 3 * kColumns);
    for (size_t i = 0; i < n; ++i) {
        const int64_t pixel = surface->pixelImageIndex(i);
        if (pixel < 0) continue;  // hidden in the atlas
        for (int c = 0; c < 3; ++c) {
            const float* d = &descriptors[(i * 3 + size_t(c)) * LabelDescriptor::kSize];
            rows.insert(rows.end(), d, d + LabelDescriptor::kSize);
            const float transmitted = (1 - fresnel) * scene.environment[c];
            rows.push_back((float(reference.mean[size_t(pixel)][c]) - fresnel * scene.environment[c]) / transmitted);
            rows.push_back(float(reference.standardError[size_t(pixel)][c]) / transmitted);
            rows.push_back(float(c));
            rows.push_back(float(i));
        }
    }
    writeNpy(*outFile, rows);
    std::printf("learned-data: %zu rows of %zu values (descriptor %d) to %s\n", rows.size() / kColumns, kColumns,
                LabelDescriptor::kSize, outFile->c_str());
    return 0;
}

}  // namespace pl
