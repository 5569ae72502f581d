// The heterogeneous medium inside the object: label grid + material table +
// per-brick majorants. Trackers are per thread (each owns an OpenVDB value
// accessor) and are never shared.
#pragma once

#include <array>
#include <memory>
#include <optional>

#include "core/enum_names.h"
#include "core/rng.h"
#include "media/label_grid.h"
#include "media/majorant_grid.h"
#include "media/materials.h"
#include "media/trackers.h"
#include "media/uniform_regions.h"
#include "media/voxel_fields.h"

namespace pl {

// What the null-collision trackers sample free flights against: the
// per-brick majorants (clear resin and void cost little), one majorant for
// the whole grid (the textbook tracker, kept to measure the bricks
// against), or per brick a control and a residual (decomposition
// tracking, trackers.h; one channel a flight: separate channel passes).
enum class Majorants { PerBrick, Global, Decomposition };
inline constexpr std::array<EnumName<Majorants>, 3> kMajorantsNames{{{Majorants::PerBrick, "bricks"},
                                                                     {Majorants::Global, "global"},
                                                                     {Majorants::Decomposition, "decomposition"}}};

// A label a path looked up (MajorantGrid::voxelKey) and how much of it
// the path used. At a null collision in channel c the path only learnt
// that the voxel's extinction in c was at most u * majorant (the
// collision's uniform times the brick's majorant): any label whose
// extinction in c stays at or below sameUpTo_perMm leaves the path as it
// is. Every other read (a real collision, labelAt, a channel of hero or
// spectral tracking) used the label itself (sameUpTo_perMm < 0).
struct LabelRead {
    uint64_t voxel = 0;
    float sameUpTo_perMm = -1.0f;
    int channel = 0;
};

// What paths read of the labels: the majorant bricks whose bounds they
// entered (MajorantGrid::brickIndex) and the labels they looked up, in any
// order, with repeats.
struct LabelReads {
    std::vector<uint32_t> bricks;
    std::vector<LabelRead> labels;
    void clear() {
        bricks.clear();
        labels.clear();
    }
};

class LabelMedium {
public:
    LabelMedium(LabelGrid grid, MaterialTable materials);
    // `grid` is `previous`'s grid with the `changed` voxels relabelled: only
    // their majorant bricks and uniform cells are recomputed (same result as
    // a full build, or majorants that only rise: MajorantGrid::update).
    LabelMedium(LabelGrid grid, const LabelMedium& previous, const std::vector<Vec3i>& changed,
                bool majorantsOnlyRise = false);

    const LabelGrid& grid() const { return grid_; }
    const GridFrame& frame() const { return grid_.frame(); }
    const MaterialTable& materials() const { return materials_; }
    const MajorantGrid& majorants() const { return majorants_; }
    // Where the grid is one material, and how far (printpt's ball walks).
    const UniformRegions& uniformRegions() const { return uniform_; }
    const ChannelLut& lut(int channel) const { return luts_[channel]; }
    const std::array<ChannelLut, 3>& luts() const { return luts_; }
    // Distance and normal fields of a prepared grid (optional; next-event
    // estimation towards the surface needs them).
    void setSurfaceFields(std::shared_ptr<const VoxelFields> fields) { fields_ = std::move(fields); }
    bool hasSurfaceFields() const { return fields_ != nullptr; }
    const std::shared_ptr<const VoxelFields>& surfaceFields() const { return fields_; }

    CellRay toCellRay(const Ray& r) const {
        return {{r.o.x * scale_.x + offset_.x, r.o.y * scale_.y + offset_.y,
                 r.o.z * scale_.z + offset_.z},
                {r.d.x * scale_.x, r.d.y * scale_.y, r.d.z * scale_.z}};
    }
    Vec3i voxelAt(const Point3f& p) const { return toCellRay({p, {0, 0, 0}}).voxelAt(0.0f); }

    // One thread's way through the medium: free flights, transmittance and
    // labels, read through its own voxel accessor.
    class Tracker {
    public:
        explicit Tracker(const LabelMedium& medium, Majorants majorants = Majorants::PerBrick);
        ~Tracker();
        Tracker(const Tracker&) = delete;
        Tracker& operator=(const Tracker&) = delete;

        // A free flight along the ray up to tMax_mm: delta tracking against
        // the tracker's majorants, or decomposition tracking.
        FreeFlight sampleFreeFlight(const Ray& ray, float tMax_mm, int channel, Rng& rng);
        // Three channels at once (media/collision_events.h): delta tracking for the
        // hero channel with log pdf ratios of the others, or spectral tracking.
        FreeFlight sampleFreeFlightHero(const Ray& ray, float tMax_mm, int hero, Rng& rng, RGB& logRatio);
        FreeFlight sampleFreeFlightSpectral(const Ray& ray, float tMax_mm, Rng& rng, RGB& weight);
        // The free flight at the given optical depth, by regular tracking.
        FreeFlight freeFlightAtDepth(const Ray& ray, float tMax_mm, int channel, float opticalDepth);
        // Transmittance by regular tracking along the ray up to tMax_mm:
        // exact, or with `roulette` an unbiased estimate that is cheaper
        // through dense resin (trackers.h).
        float transmittance(const Ray& ray, float tMax_mm, int channel, TransmittanceRoulette roulette = {});
        // Unbiased estimates of the same, by ratio tracking against the
        // brick majorants or by pins over the voxels (segment_transmittance.h).
        float ratioTrackedTransmittance(const Ray& ray, float tMax_mm, int channel, Rng& rng);
        float pinTransmittance(const Ray& ray, float tMax_mm, int channel, Rng& rng);
        Label labelAt(const Vec3i& voxel);
        // Where the tracker's answers came from, from now on (none: stop
        // recording): the bricks whose bounds a free flight entered and
        // the labels it or labelAt read (LabelReads). A path none of whose
        // bricks changed its bounds and none of whose reads a relabelling
        // contradicts is the same path after the change. Free flights
        // against per-brick majorants and labelAt only: regular tracking,
        // the global majorant and decomposition tracking are not recorded.
        void recordReads(LabelReads* reads) { reads_ = reads; }
        // Outward normal of the nearest surface and signed distance (mm) at
        // p, from the surface fields; none outside their band.
        struct NearestSurface {
            Vec3f normal;
            float sdf_mm;
        };
        std::optional<NearestSurface> nearestSurface(const Point3f& p);

    private:
        // The null-collision trackers' loop (trackers.h) over the tracker's
        // majorants, with the events policy (collision_events.h).
        template <class Events>
        FreeFlight sampleFlight(const Ray& ray, float tMax_mm, Events& events, Rng& rng);
        struct Impl;
        std::unique_ptr<Impl> impl_;
        const LabelMedium& medium_;
        Majorants majorants_;
        LabelReads* reads_ = nullptr;
    };

private:
    LabelGrid grid_;
    MaterialTable materials_;
    std::array<ChannelLut, 3> luts_;
    MajorantGrid majorants_;
    UniformRegions uniform_;
    Vec3f scale_, offset_;
    std::shared_ptr<const VoxelFields> fields_;
};

// Per channel, over the labels the grid holds (void aside; one pass over
// the grid): the least extinction, and the largest scattering coefficient
// (at least 1e-6 /mm).
struct GridCoefficients {
    RGB leastSigmaT{1e30f, 1e30f, 1e30f};
    RGB mostSigmaS{1e-6f, 1e-6f, 1e-6f};
};
GridCoefficients gridCoefficientsOf(const LabelMedium& medium);

}  // namespace pl
