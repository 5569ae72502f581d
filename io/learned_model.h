// A trained predictor (scripts/train_learned.py): a small multilayer
// perceptron from one channel's label descriptor (integrators/learned/label_descriptor.h) to
// that channel's surface response, with what it was trained for. It is
// valid only for that material table and voxel size.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/rgb.h"
#include "core/vecmath.h"
#include "media/materials.h"

namespace pl {

struct LearnedModel {
    std::string file;  // where it was read from (for messages)
    // What it was trained for.
    MaterialTable materials;
    Vec3f voxelSize_mm{0, 0, 0};
    int descriptorSize = 0;
    // Dense layers, ReLU between them; the input normalisation is folded
    // into the first. weights: outputs x inputs, row-major.
    struct Layer {
        int inputs = 0, outputs = 0;
        std::vector<float> weights, bias;
    };
    std::vector<Layer> layers;
    // The error bound of a prediction R: errorShare x R + errorFloor (on
    // held-out renders, 95 % of voxel channels lie within twice it,
    // counting the renders' own noise).
    float errorShare = 0, errorFloor = 0;

    // Why this model cannot predict a scene with these materials and
    // voxels (empty: it can).
    std::string refusal(const MaterialTable& scene, const Vec3f& sceneVoxel_mm) const;
};

}  // namespace pl
