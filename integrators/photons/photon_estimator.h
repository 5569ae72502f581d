// What every progressive photon estimator (bre, pp3d, pb2d, bb1d, combined) declares
// the same way: its capabilities and the unit of what it gathers.
#pragma once

#include "integrators/integrator.h"
#include "scene/scene.h"

namespace pl {

// Every sensor, its light paths serving every pixel; volpath's walk looks
// for the clearance first.
inline IntegratorCapabilities photonCapabilities() {
    IntegratorCapabilities c;
    c.needs = {false, true};
    c.lightPathsServeEveryPixel = true;
    return c;
}

// What photons gather is the radiance inside, n^2 times the path tracers'
// unit: this turns it into theirs.
inline double insideToOutside(const Scene& scene) { return 1.0 / (double(scene.ior) * scene.ior); }

}  // namespace pl
