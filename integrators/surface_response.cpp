#include "integrators/surface_response.h"

#include <algorithm>
#include <cmath>

#include "core/fresnel.h"
#include "runtime/scheduler.h"

namespace pl {

SurfaceResponse::~SurfaceResponse() = default;

IntegratorCapabilities SurfaceResponse::capabilities(const RenderSettings&) {
    IntegratorCapabilities c;
    c.deterministic = true;
    return c;
}

SurfaceResponse::SurfaceResponse(const Scene& scene, const Sensor& sensor) : scene_(scene) {
    // Predictors look at the surface around each element: they need all of
    // it, the sensor's patches if it has every surface voxel's, else the
    // grid's own.
    surface_ = dynamic_cast<const SurfaceVoxelSensor*>(&sensor);
    if (!surface_ || !surface_->patches()) surface_ = nullptr;
    const std::vector<SurfaceVoxel> surfaceVoxels = scene.medium->grid().surfaceVoxels();
    if (!surface_ || surface_->pixelCount() != surfaceVoxels.size()) {
        ownSurface_ = std::make_unique<SurfaceVoxelSensor>(*scene.geometry, scene.medium->frame(), surfaceVoxels,
                                                           SurfaceVoxelSensor::Footprint::Patch);
        surface_ = ownSurface_.get();
    }
    response_.assign(elementCount(), RGB{0, 0, 0});
    errorBound_.assign(elementCount(), RGB{0, 0, 0});
}

void SurfaceResponse::coverElementsOverClearResin() {
    constexpr float kDepth_mm = 1.0f, kLeastOpticalDepth = 1.0f;
    const LabelMedium& medium = *scene_.medium;
    // Only a grid that holds some resin that clear needs the walk.
    const RGB leastSigmaT = gridCoefficientsOf(medium).leastSigmaT;
    if (!(std::min({leastSigmaT[0], leastSigmaT[1], leastSigmaT[2]}) * kDepth_mm < kLeastOpticalDepth)) return;
    std::vector<uint8_t> over(elementCount(), 0);
    parallelForTiles(elementCount(), 256, [&](size_t begin, size_t end) {
        LabelMedium::Tracker sampler(medium);
        for (size_t i = begin; i < end; ++i) {
            const SurfacePoint e = surfacePoint(i);
            const Ray inward{e.p, -e.normal};
            bool isOver = false;
            for (int c = 0; c < kChannels && !isOver; ++c)
                isOver = sampler.transmittance(inward, kDepth_mm, c) > std::exp(-kLeastOpticalDepth);
            if (!isOver) continue;
            over[i] = 1;
            for (int c = 0; c < kChannels; ++c) errorBound_[i][c] = std::max(response_[i][c], 1.0f - response_[i][c]);
        }
    });
    elementsOverClearResin_ = size_t(std::count(over.begin(), over.end(), uint8_t(1)));
}

SurfacePoint surfacePointOf(const SurfaceVoxelSensor& surface, size_t i) {
    const SurfaceVoxelSensor::Pixel& pixel = surface.pixels()[i];
    const SurfacePatches& patches = *surface.patches();
    SurfacePoint e{pixel.surfacePoint_mm, pixel.normal, float(patches.area_mm2(i))};
    if (e.area_mm2 > 0) {
        Point3f weighted(0, 0, 0);
        Vec3f n(0, 0, 0);
        patches.forEachPiece(i, [&](const SurfacePatches::Piece& piece) {
            weighted += (piece.a + piece.b + piece.c) * (piece.area_mm2 / 3.0f);
            n += patches.normal(piece) * piece.area_mm2;
            return true;
        });
        e.p = weighted / e.area_mm2;
        if (length(n) > 0) e.normal = normalize(n);
    }
    return e;
}

RGB SurfaceResponse::radiance(const Ray& ray, int reflectionsLeft, RGB* bound) const {
    const RGB& Le = scene_.environment;
    const std::optional<SurfaceHit> hit = scene_.geometry->intersect(ray);
    if (!hit) return Le;
    if (dot(ray.d, hit->ng) >= 0) return {0, 0, 0};  // from inside: not a view of the surface
    const float cosine = std::clamp(-dot(ray.d, hit->ns), 0.0f, 1.0f);
    const float fresnel = fresnelDielectric(cosine, scene_.ior);
    RGB mirrored = Le;
    if (reflectionsLeft > 0)
        mirrored = radiance(scene_.geometry->spawnRay(hit->p, hit->ng, reflectOnSide(ray.d, *hit)), reflectionsLeft - 1,
                            nullptr);
    RGB L;
    for (int c = 0; c < kChannels; ++c) L[c] = fresnel * mirrored[c];
    const std::optional<uint32_t> element = surface_->patches()->pixelAt(hit->prim, hit->p);
    if (!element) return L;
    for (int c = 0; c < kChannels; ++c) {
        L[c] += (1.0f - fresnel) * Le[c] * response_[*element][c];
        if (bound) (*bound)[c] = (1.0f - fresnel) * Le[c] * errorBound_[*element][c];
    }
    return L;
}

ChannelSample SurfaceResponse::Li(Ray ray, int channel, LabelMedium::Tracker&, Rng&, PathStats& stats) const {
    RGB bound{0, 0, 0};
    const RGB L = radiance(ray, 1, &bound);
    ++stats.paths;
    ChannelSample sample;
    sample.value = L[channel];
    sample.sharedError = bound[channel];
    return sample;
}

RGB SurfaceResponse::LiRGB(Ray ray, ChannelSampling, int, LabelMedium::Tracker&, Rng&, PathStats& stats) const {
    ++stats.paths;
    return radiance(ray, 1, nullptr);
}

}  // namespace pl
