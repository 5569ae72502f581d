#include "io/printpt_settings.h"

#include <stdexcept>

namespace pl {

const std::vector<PrintPtKey>& printPtKeys() {
    using K = PrintPtKey::Kind;
    static const std::vector<PrintPtKey> keys = {
        {"branches", K::Integer},
        {"rr_cap", K::Number},
        {"rr_threshold", K::Number},
        {"rr_threshold_absorbing", K::Number},
        {"fresnel_weighting", K::Boolean},
        {"medium_first", K::Boolean},
        {"clearance", K::Boolean},
        {"ball_walks", K::Boolean},
        {"ball_min_mfp", K::Number},
        {"nee", K::Boolean},
        {"nee_max_kappa", K::Number},
        {"nee_prune_scale", K::Number},
        {"nee_min_probability", K::Number},
        {"nee_roulette_depth", K::Number},
        {"control_variate", K::Boolean},
        {"control_walks", K::Integer},
        {"control_probe", K::Number},
        {"control_probe_short", K::Number},
        {"control_edge_reach", K::Number},
        {"control_curved", K::Boolean},
        {"control_curved_thickness", K::Number},
        {"control_curved_tolerance", K::Number},
        {"control_continuations", K::Integer},
        {"control_mean_walks_per_entry", K::Integer},
    };
    return keys;
}

std::string setPrintPtOption(PrintPtOptions& o, const std::string& key, double value) {
    const bool on = value != 0.0;
    if (key == "branches") {
        if (!(value >= 1 && value <= 1024) || value != double(int(value))) return "must be a whole number in 1..1024";
        o.branches = int(value);
    } else if (key == "rr_cap" || key == "rr_threshold" || key == "rr_threshold_absorbing") {
        if (!(value > 0 && value <= 1)) return "must be in (0, 1]";
        (key == "rr_cap" ? o.rrCap : key == "rr_threshold" ? o.rrThreshold : o.rrThresholdAbsorbing) = float(value);
    } else if (key == "ball_min_mfp") {
        if (!(value >= 0 && value <= 1e6)) return "must be a number of mean free paths >= 0";
        o.ballMinMfp = float(value);
    } else if (key == "fresnel_weighting") {
        o.fresnelWeighting = on;
    } else if (key == "medium_first") {
        o.mediumFirst = on;
    } else if (key == "clearance") {
        o.clearance = on;
    } else if (key == "ball_walks") {
        o.ballWalks = on;
    } else if (key == "nee") {
        o.nee = on;
    } else if (key == "nee_max_kappa") {
        if (!(value >= 1 && value <= 1e4)) return "must be a concentration in 1..1e4";
        o.neeMaxKappa = float(value);
    } else if (key == "nee_prune_scale") {
        if (!(value > 0 && value <= 1e6)) return "must be a number > 0";
        o.neePruneScale = float(value);
    } else if (key == "nee_min_probability") {
        if (!(value >= 0 && value <= 1)) return "must be in [0, 1]";
        o.neeMinProbability = float(value);
    } else if (key == "nee_roulette_depth") {
        if (!(value > 0 && value <= 100)) return "must be an optical depth in (0, 100]";
        o.neeRouletteDepth = float(value);
    } else if (key == "control_curved") {
        o.controlCurved = on;
    } else if (key == "control_curved_thickness") {
        if (!(value >= 0 && value <= 100)) return "must be a number of diffusion lengths in 0..100";
        o.controlCurvedThickness = float(value);
    } else if (key == "control_curved_tolerance") {
        if (!(value > 0 && value <= 100)) return "must be a number of mean free paths in (0, 100]";
        o.controlCurvedTolerance = float(value);
    } else if (key == "control_variate") {
        o.controlVariate = on;
    } else if (key == "control_probe" || key == "control_probe_short") {
        if (!(value >= 0 && value <= 100)) return "must be a number of diffusion lengths in 0..100";
        (key == "control_probe" ? o.controlProbe : o.controlProbeShort) = float(value);
    } else if (key == "control_continuations") {
        if (!(value >= 1 && value <= 1024) || value != double(int(value))) return "must be a whole number in 1..1024";
        o.controlContinuations = int(value);
    } else if (key == "control_mean_walks_per_entry") {
        if (!(value >= 0 && value <= 1e9) || value != double(int64_t(value))) return "must be a whole number in 0..1e9";
        o.controlMeanWalksPerEntry = int64_t(value);
    } else if (key == "control_edge_reach") {
        if (!(value >= 0 && value <= 100)) return "must be a number of diffusion lengths in 0..100";
        o.controlEdgeReach = float(value);
    } else if (key == "control_walks") {
        if (!(value >= 1024 && value <= 1e9) || value != double(int64_t(value)))
            return "must be a whole number of walks in 1024..1e9";
        o.controlWalks = int64_t(value);
    } else {
        throw std::invalid_argument("unknown printpt option '" + key + "'");
    }
    return "";
}

}  // namespace pl
