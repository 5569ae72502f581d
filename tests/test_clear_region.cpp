// Where a kernel stays inside (integrators/photons/clear_region.h):
// ClearAlong answers as isClear does, at points along flights through a
// box, both near its faces and deep.
#include <gtest/gtest.h>

#include "core/sampling.h"
#include "integrators/photons/clear_region.h"
#include "progressive_estimate.h"

namespace pl {
namespace {

TEST(ClearRegion, ClearAlongAnswersAsIsClear) {
    const Scene scene = test::colouredPhotonBox(1.5f);
    const GridFrame& frame = scene.medium->frame();
    const float reach_mm = clearReach_mm(scene, 0.08f);
    Rng rng(17, 0);
    size_t clear = 0, notClear = 0;
    for (int f = 0; f < 300; ++f) {
        Point3f o;
        for (int a = 0; a < 3; ++a)
            o[a] = frame.cornerMin_mm[a] + rng.uniform() * float(frame.resolution[a]) * frame.voxelSize_mm[a];
        const PhaseSample direction = sampleHG(Vec3f{0, 0, 1}, 0.0f, rng.uniform(), rng.uniform());
        const Ray flight{o, direction.dOut};
        ClearAlong along(scene, flight, reach_mm, 0.08f);
        for (int i = 0; i < 20; ++i) {
            const float t_mm = 0.4f * rng.uniform();
            const bool expected = isClear(scene, flight.at(t_mm), reach_mm);
            EXPECT_EQ(along.at(t_mm), expected) << "flight " << f << ", t " << t_mm;
            (expected ? clear : notClear) += 1;
        }
    }
    EXPECT_GT(clear, 300u);
    EXPECT_GT(notClear, 300u);
}

}  // namespace
}  // namespace pl
