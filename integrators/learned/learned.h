// learned: the trained predictor (after Rittig et al. 2021; the
// training in scripts/train_learned.py, measurements in docs/learned.md).
// Deterministic: per surface element, the descriptor of the labels under
// it (label_descriptor.h) goes through the model's perceptron, one channel
// at a time; rays read the result as for every surface-response predictor
// (surface_response.h), with the model's error bound.
#pragma once

#include <memory>

#include "integrators/learned/label_descriptor.h"
#include "io/learned_model.h"
#include "integrators/surface_response.h"

namespace pl {

class Learned : public SurfaceResponse {
public:
    // Throws InputError when the model was trained for other materials or voxels.
    Learned(const Scene& scene, const Sensor& sensor, std::shared_ptr<const LearnedModel> model);
    // learned_model: the model's file (io/learned_model_io.h), by default
    // the one beside the scene's material table.
    static std::vector<ParameterInfo> parameters();
    // Its model is read up front; whether it was trained for the scene's
    // materials and voxels is known once the scene is loaded.
    static std::string refusal(const RenderSettings& settings);
    static std::unique_ptr<Integrator> create(const Scene& scene, const Sensor& sensor, const RenderSettings& settings);
};

// The descriptors of elements [begin, end) of a surface-voxel sensor with
// patches, three rows (channels) per element, into `out` (the integrator's
// inputs, and the training data's: apps/learned_data_command.cpp).
void describeSurface(const LabelDescriptor& descriptor, const SurfaceVoxelSensor& surface, size_t begin, size_t end,
                     LabelMedium::Tracker& sampler, float* out);

// The perceptron over a batch: inputs are `count` rows of model.descriptorSize.
void evaluateLearnedModel(const LearnedModel& model, const float* inputs, size_t count, float* outputs);

}  // namespace pl
