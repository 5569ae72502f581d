#include "integrators/printpt/printpt_options.h"

namespace pl {

const std::vector<PrintPtParameter>& printPtParameters() {
    using O = PrintPtOptions;
    constexpr const char* kDiffusion = "must be a number of diffusion lengths in 0..100";
    static const std::vector<PrintPtParameter> parameters = {
        {"branches", &O::branches, 1, 1024, false, "must be a whole number in 1..1024",
         "walks from each entry point, weight 1/k each"},
        {"rr_cap", &O::rrCap, 0, 1, true, "must be in (0, 1]", "Russian roulette's highest survival probability"},
        {"rr_threshold", &O::rrThreshold, 0, 1, true, "must be in (0, 1]",
         "throughput below which Russian roulette plays (survival throughput / threshold)"},
        {"rr_threshold_absorbing", &O::rrThresholdAbsorbing, 0, 1, true, "must be in (0, 1]",
         "the threshold at collisions in absorbing resin (albedo below 0.5)"},
        {"fresnel_weighting", &O::fresnelWeighting, 0, 0, false, "", "keep reflected and transmitted parts as weights"},
        {"medium_first", &O::mediumFirst, 0, 0, false, "", "sample the collision first, query the boundary up to it"},
        {"clearance", &O::clearance, 0, 0, false, "", "skip boundary queries for collisions nearer than the surface"},
        {"ball_walks", &O::ballWalks, 0, 0, false, "", "walk deep in one material without lookups, ball by ball"},
        {"ball_min_mfp", &O::ballMinMfp, 0, 1e6, false, "must be a number of mean free paths >= 0",
         "smallest ball worth a ball walk, in mean free paths"},
        {"nee", &O::nee, 0, 0, false, "", "next-event estimation towards the nearest surface (needs sdf/normal grids)"},
        {"nee_max_kappa", &O::neeMaxKappa, 1, 1e4, false, "must be a concentration in 1..1e4",
         "largest concentration of NEE's von Mises-Fisher lobe"},
        {"nee_prune_scale", &O::neePruneScale, 0, 1e6, true, "must be a number > 0",
         "NEE runs with probability min(1, scale exp(-optical depth))"},
        {"nee_min_probability", &O::neeMinProbability, 0, 1, false, "must be in [0, 1]",
         "the least probability with which NEE runs"},
        {"nee_roulette_depth", &O::neeRouletteDepth, 0, 100, true, "must be an optical depth in (0, 100]",
         "optical depth past which NEE's transmittance is tracked with Russian roulette"},
        {"control_variate", &O::controlVariate, 0, 0, false, "",
         "each walk coupled to a walk in a region of known mean (integrators/printpt/control_variate.h)"},
        {"control_walks", &O::controlWalks, 1024, 1e9, false, "must be a whole number of walks in 1024..1e9",
         "Monte Carlo walks behind a wedge's mean (x 1/4) or a curved region's (x 1/32)"},
        {"control_probe", &O::controlProbe, 0, 100, false, kDiffusion,
         "reach, in diffusion lengths, over which the control's region must fit"},
        {"control_probe_short", &O::controlProbeShort, 0, 100, false, kDiffusion,
         "a second, shorter reach where the first fails on thick parts; 0: none"},
        {"control_edge_reach", &O::controlEdgeReach, 0, 100, false, kDiffusion,
         "how far a right-angled edge is looked for (wedge controls); 0: none"},
        {"control_curved", &O::controlCurved, 0, 0, false, "", "controls under convex curved surfaces (paraboloids)"},
        {"control_curved_thickness", &O::controlCurvedThickness, 0, 100, false, kDiffusion,
         "the ball the object must hold below a curved control's entry"},
        {"control_curved_tolerance", &O::controlCurvedTolerance, 0, 100, true,
         "must be a number of mean free paths in (0, 100]",
         "how far the tabulated paraboloid may be from the surface"},
        {"control_continuations", &O::controlContinuations, 1, 1024, false, "must be a whole number in 1..1024",
         "independent continuations of a control that parted"},
        {"control_mean_walks_per_entry", &O::controlMeanWalksPerEntry, 0, 1e9, false,
         "must be a whole number in 0..1e9",
         "a costly control runs where its mean's walks come to at most this many per surveyed entry"},
    };
    return parameters;
}

}  // namespace pl
