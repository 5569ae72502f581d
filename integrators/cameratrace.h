// cameratrace: light tracing into a perspective camera through the
// object's flat faces, for previews. A pixel's value, the mean radiance over
// its film area, is split as lighttrace splits a patch's:
//  - the camera side: the environment reflected where the pixel's ray
//    enters and what comes along its refracted first segment without
//    scattering there (unscatteredCameraSide);
//  - the light side: light scattered last on that segment. Particles enter
//    from the environment (uniform by area, cosine-weighted, Le pi A / N
//    times the Fresnel transmission) and walk with volpath's walk; at each
//    real collision y a particle connects to the pinhole through every
//    face plane that faces it: the point x of the plane where the ray from
//    y refracts towards the pinhole (Snell's law in the plane of incidence,
//    one monotone equation), kept where the pinhole sees x first and x sees
//    y. It scores, in the pixel the ray lands in, its power x phase x
//    transmittance y->x x Fresnel transmission out x the pinhole's
//    importance x the refracted bundle's d omega_y / dA (Walter et al.
//    2009's generalised geometry term for a flat interface):
//      1 / ((d1 + n d2) (d1 cos2 / cos1 + n d2 cos1 / cos2)),
//    d1 = |y - x|, d2 = |x - pinhole|, cos1 and cos2 the angles to the
//    plane's normal inside and out.
// Each sample is one block of particles plus every pixel's camera sample;
// its error is the spread of the samples. Separate channel passes; meshes
// of at most kMostPlanes distinct planes (boxes, prisms: flat-faced prints).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/mesh_point_sampler.h"
#include "core/option_table.h"
#include "core/sensors.h"
#include "integrators/integrator.h"
#include "integrators/volpath.h"

namespace pl {

struct CameraTraceOptions {
    // Particles per block (per sample) for each camera pixel.
    double particlesPerPixel = 1.0;
};
// Its options by their scene-file names (core/option_table.h).
const std::vector<OptionParameter<CameraTraceOptions>>& cameraTraceParameters();

class CameraTrace : public Integrator {
public:
    // The sensor must be perspective and the mesh of at most kMostPlanes
    // planes (std::invalid_argument otherwise).
    CameraTrace(const Scene& scene, const Sensor& sensor, CameraTraceOptions options, Majorants majorants,
                uint64_t seed);

    static IntegratorCapabilities capabilities(const RenderSettings& settings);
    static std::string refusal(const RenderSettings& settings) {
        return refusalWithoutReentry("cameratrace", settings);
    }
    static std::unique_ptr<Integrator> create(const Scene& scene, const Sensor& sensor, const RenderSettings& settings,
                                              std::shared_ptr<HalfSpaceMeans> controlMeans);

    // Sample by sample, the block of particles, then every pixel's camera
    // side plus the block's score there.
    void render(const RenderPass& pass, Film& film, PathStats& stats, ProgressBar& progress) const override;
    // Sample `sample`'s block of particles in a channel, scored per pixel.
    std::vector<double> scoreBlock(int channel, uint32_t sample, PathStats& stats) const;

    static constexpr size_t kMostPlanes = 64;
    // A block's particles are cut into this many parts, traced in parallel
    // and added in part order (the same bits whatever the threads).
    static constexpr size_t kParts = 16;

    struct Plane {
        Vec3f n;        // outward unit normal
        float offset;   // dot(n, x) on the plane
    };
    // The distinct planes of the mesh's triangles.
    static std::vector<Plane> planesOf(const TriangleMesh& mesh);

private:
    // Scores a collision at y (propagation direction dIn before it, label
    // and path weight beta) into the pixels it reaches through each face.
    template <class Score>
    void connect(const Point3f& y, const Vec3f& dIn, Label label, double power, int channel,
                 LabelMedium::Tracker& medium, Rng& rng, Score&& score) const;

    const Scene& scene_;
    const PerspectiveSensor& camera_;
    CameraTraceOptions options_;
    Majorants majorants_;
    VolPath volpath_;
    uint64_t lightSeed_;
    MeshPointSampler entries_;
    std::vector<Plane> planes_;  // those the pinhole lies outside of
    RGB leastSigmaT_;            // per channel, over the labels in the grid (the connections' roulette)
};

}  // namespace pl
