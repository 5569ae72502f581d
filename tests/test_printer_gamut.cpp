// The printer's gamut (prepare/printer_gamut.h) and its characterisation
// (api/printer_characterisation.h): the interpolation on the mixing
// simplex, the inverse, the mapping into the gamut, the characterisation
// against independent renders, and the cache.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "api/appearance_optimizer.h"
#include "api/printer_characterisation.h"
#include "io/grid_io.h"
#include "io/mesh_io.h"
#include "render/scene_io.h"
#include "compare/colour_difference.h"
#include "core/rng.h"
#include "core/sensors.h"
#include "io/materials_io.h"
#include "io/printer_gamut_io.h"
#include "prepare/rendering_intent.h"
#include "render/render.h"
#include "test_util.h"

namespace pl {
namespace {

// A random point of the mixing simplex (uniform: normalised exponentials).
MaterialFractions randomMixture(Rng& rng) {
    MaterialFractions m;
    float sum = 0;
    for (float& x : m) sum += (x = -std::log(std::max(rng.uniform(), 1e-7f)));
    for (float& x : m) x /= sum;
    return m;
}

// Kubelka-Munk's reflectance for K/S linear in the mixture: the forward
// model's interpolation is exact for it.
RGB linearKmReflectance(const MaterialFractions& m) {
    const float ks[5][3] = {{2.0f, 0.1f, 0.15f}, {0.1f, 1.5f, 0.3f}, {0.05f, 0.1f, 3.0f}, {4, 4, 4}, {0.02f, 0.03f, 0.05f}};
    RGB r;
    for (int c = 0; c < 3; ++c) {
        double k = 0;
        for (int i = 0; i < 5; ++i) k += m[size_t(i)] * ks[i][c];
        r[size_t(c)] = float(1 + k - std::sqrt(k * k + 2 * k));
    }
    return r;
}

PrinterGamut gamutOf(int levels, RGB (*reflectanceOf)(const MaterialFractions&)) {
    std::vector<RGB> r, e;
    for (const MaterialFractions& m : PrinterGamut::gridMixtures(levels)) {
        r.push_back(reflectanceOf(m));
        e.push_back({0, 0, 0});
    }
    return PrinterGamut(levels, r, e);
}

TEST(PrinterGamut, GridCoversTheSimplex) {
    for (int levels : {1, 2, 4, 8}) {
        const auto grid = PrinterGamut::gridMixtures(levels);
        // Compositions of `levels` into five parts: C(levels + 4, 4).
        const size_t expected = size_t(levels + 1) * (levels + 2) * (levels + 3) * (levels + 4) / 24;
        EXPECT_EQ(grid.size(), expected);
        for (const MaterialFractions& m : grid) {
            float sum = 0;
            for (float x : m) {
                EXPECT_GE(x, 0.0f);
                sum += x;
            }
            EXPECT_NEAR(sum, 1.0f, 1e-6f);
        }
    }
}

TEST(PrinterGamut, InterpolationIsExactWhereKubelkaMunkIsLinear) {
    const PrinterGamut gamut = gamutOf(3, linearKmReflectance);
    Rng rng(7, 0);
    for (int k = 0; k < 2000; ++k) {
        const MaterialFractions m = randomMixture(rng);
        const RGB want = linearKmReflectance(m), got = gamut.reflectance(m);
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(got[size_t(c)], want[size_t(c)], 2e-5f) << k;
    }
    // On the simplex's faces and corners too.
    for (const MaterialFractions& m : PrinterGamut::gridMixtures(6)) {
        const RGB want = linearKmReflectance(m), got = gamut.reflectance(m);
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(got[size_t(c)], want[size_t(c)], 2e-5f);
    }
}

// A forward model that is not linear in K/S: the inverse must still reach
// every colour of the gamut (mapping is the identity inside it), and
// outside it land no farther than any mixture tried at random.
RGB curvedReflectance(const MaterialFractions& m) {
    RGB r = linearKmReflectance(m);
    for (float& x : r) x = x * (0.8f + 0.2f * x);
    return r;
}

TEST(PrinterGamut, InverseReachesEveryColourInsideAndTheNearestOutside) {
    const PrinterGamut gamut = gamutOf(4, curvedReflectance);
    Rng rng(11, 0);
    double worst = 0;
    for (int k = 0; k < 300; ++k) {
        const Lab target = gamut.colour(randomMixture(rng));
        const PrinterGamut::Match m = gamut.closest(target);
        worst = std::max(worst, m.deltaEab);
        EXPECT_LT(ciede2000(m.colour, target), 0.05) << k;
    }
    std::printf("inside the gamut: the inverse's worst Delta E*ab %.4f\n", worst);
    // The characterised colours themselves are inside.
    for (const MaterialFractions& g : PrinterGamut::gridMixtures(4))
        EXPECT_LT(gamut.closest(gamut.colour(g)).deltaEab, 0.05);
    // Outside: saturated and extreme colours. No mixture of a dense random
    // sample is nearer than the match.
    std::vector<Lab> sample;
    for (int k = 0; k < 20000; ++k) sample.push_back(gamut.colour(randomMixture(rng)));
    for (const MaterialFractions& g : PrinterGamut::gridMixtures(12)) sample.push_back(gamut.colour(g));
    const Lab outside[] = {{50, 80, 60}, {90, -40, 80}, {30, 20, -70}, {98, 0, 0}, {2, 0, 0}, {60, -70, -20}};
    for (const Lab& t : outside) {
        const PrinterGamut::Match m = gamut.closest(t);
        double nearest = 1e30;
        for (const Lab& s : sample)
            nearest = std::min(nearest, double(std::hypot(s.L - t.L, std::hypot(s.a - t.a, s.b - t.b))));
        EXPECT_LE(m.deltaEab, nearest + 0.05) << t.L << " " << t.a << " " << t.b;
        EXPECT_GT(m.deltaEab, 1.0);  // truly outside
    }
}

// The boundary descriptor against the gamut's own inverse: every printable
// colour lies within it, and its surface lies on the gamut's.
TEST(GamutBoundary, HoldsTheGamutAndLiesOnItsSurface) {
    const PrinterGamut gamut = gamutOf(4, linearKmReflectance);
    const GamutBoundary boundary(gamut);
    Rng rng(5, 0);
    // Segment maxima lie a little inside the true boundary: few printable
    // colours beyond them, none far.
    double worstOutside = 0;
    int outside = 0;
    for (int k = 0; k < 3000; ++k) {
        const Lab c = gamut.colour(randomMixture(rng));
        const double beyond = std::hypot(c.a, c.b) - boundary.maxChroma(c.L, hueDegrees(c));
        worstOutside = std::max(worstOutside, beyond);
        outside += beyond > 1.0;
    }
    std::printf("printable colours beyond the boundary by over 1 Delta C*ab: %d of 3000, worst %.2f\n", outside,
                worstOutside);
    EXPECT_LT(outside, 10);
    EXPECT_LT(worstOutside, 5.0);
    // Continuous across 0 / 360 degrees.
    for (double L : {40.0, 60.0, 80.0})
        EXPECT_NEAR(boundary.maxChroma(L, 359.99), boundary.maxChroma(L, 0.01), 0.05) << L;
    double sum = 0, worst = 0;
    int count = 0;
    for (int h = 0; h < 360; h += 15)
        for (double t : {0.2, 0.4, 0.6, 0.8}) {
            const double L = boundary.darkestL() + t * (boundary.lightestL() - boundary.darkestL());
            const double C = boundary.maxChroma(L, h);
            const double rad = h * double(kPi) / 180.0;
            const Lab onSurface{float(L), float(C * std::cos(rad)), float(C * std::sin(rad))};
            const double off = gamut.closest(onSurface).deltaEab;  // 0 inside, the distance outside
            sum += off;
            worst = std::max(worst, off);
            ++count;
        }
    std::printf("boundary on the gamut's surface: mean %.3f, worst %.3f Delta E*ab beyond it\n", sum / count, worst);
    EXPECT_LT(sum / count, 0.15);
    EXPECT_LT(worst, 1.0);
}

// The perceptual intent keeps hue, keeps the order of lightness and of
// chroma, lands inside the gamut and leaves the inner chroma alone.
TEST(RenderingIntent, PerceptualKeepsHueAndOrderInsideTheGamut) {
    const PrinterGamut gamut = gamutOf(4, linearKmReflectance);
    const PerceptualIntent perceptual(gamut);
    const GamutBoundary boundary(gamut);
    Rng rng(9, 0);
    for (int k = 0; k < 400; ++k) {
        const RGB rgb{rng.uniform(), rng.uniform(), rng.uniform()};
        const Lab in = labFromLinearSrgb(rgb), out = perceptual(in);
        EXPECT_LT(gamut.closest(out).deltaEab, 2.0) << rgb[0] << " " << rgb[1] << " " << rgb[2];
        // Never pushed outwards: chroma falls or stays.
        EXPECT_LE(std::hypot(out.a, out.b), std::hypot(in.a, in.b) + 1e-3);
        if (std::hypot(in.a, in.b) > 5) {
            double dh = std::abs(hueDegrees(out) - hueDegrees(in));
            EXPECT_LT(std::min(dh, 360 - dh), 0.01);
        }
    }
    // Greys: black and white to the printer's, in order between.
    double before = -1;
    for (float g = 0; g <= 1.0001f; g += 0.05f) {
        const Lab out = perceptual(labFromLinearSrgb({g, g, g}));
        EXPECT_GT(out.L, before);
        before = out.L;
        if (g == 0) {
            EXPECT_NEAR(out.L, boundary.darkestL(), 0.01);
        }
    }
    EXPECT_NEAR(before, boundary.lightestL(), 0.01);
    // At the cusp's lightness of a red hue, chroma rising to sRGB's boundary: the
    // chroma it maps to keeps rising, and the most saturated colours stay
    // apart where clipping merges them onto the gamut's surface.
    const double hue = 30 * double(kPi) / 180;
    const float cuspL = float(boundary.cuspLightness(30));
    auto atChroma = [&](double C) { return Lab{cuspL, float(C * std::cos(hue)), float(C * std::sin(hue))}; };
    double sRgbChroma = 0;
    for (double C = 0;; C += 0.25) {
        const RGB rgb = linearSrgbFromLab(atChroma(C));
        if (*std::min_element(rgb.begin(), rgb.end()) < 0 || *std::max_element(rgb.begin(), rgb.end()) > 1) break;
        sRgbChroma = C;
    }
    double lastChroma = -1;
    std::vector<Lab> outs, clipped;
    for (int k = 0; k <= 10; ++k) {
        const Lab in = atChroma(sRgbChroma * k / 10.0), out = perceptual(in);
        const double chroma = std::hypot(out.a, out.b);
        EXPECT_GT(chroma, lastChroma) << k;
        lastChroma = chroma;
        outs.push_back(out);
        clipped.push_back(gamut.closest(in).colour);
    }
    // Clipping keeps the colours inside the gamut as they are; the
    // perceptual intent moves them too, to make room for the rest.
    int inside = 0;
    while (inside < 10 && ciede2000(clipped[size_t(inside) + 1], atChroma(sRgbChroma * (inside + 1) / 10.0)) < 0.05)
        ++inside;
    ASSERT_GE(inside, 1);
    std::printf("sRGB's most saturated red at L* %.1f (C* %.1f) -> C* %.1f; at %d0 %% of it (inside the gamut) %.2f "
                "from clipping's\n",
                cuspL, sRgbChroma, lastChroma, inside, ciede2000(outs[size_t(inside)], clipped[size_t(inside)]));
    EXPECT_GT(ciede2000(outs[size_t(inside)], clipped[size_t(inside)]), 0.5);
    // Colours within the knee: only their lightness moves, their a* and b*
    // stay, saturated ones (half the way to the boundary) too.
    for (int h = 0; h < 360; h += 30) {
        const double L = boundary.cuspLightness(h), C = 0.5 * boundary.maxChroma(L, h);
        const double rad = h * double(kPi) / 180.0;
        const Lab inner{float(L), float(C * std::cos(rad)), float(C * std::sin(rad))};
        const Lab innerOut = perceptual(inner);
        EXPECT_NEAR(innerOut.a, inner.a, 1e-4) << h;
        EXPECT_NEAR(innerOut.b, inner.b, 1e-4) << h;
    }
}

// prepare's mixtures: on the bundled resins' characterisation, colours the
// printer can show (random mixtures') come back from the gamut's inverse
// (through GamutMixing's rounding) and are printed within a fraction of a
// unit; the simple subtractive model misses them by far more.
TEST(PrinterGamut, PrepareMixingFromTheGamutBeatsTheSimpleModel) {
    const auto gamut = readPrinterGamut(test::sourceDir() / "data/materials/resins_illustrative.gamut.json", "");
    ASSERT_TRUE(gamut);
    GamutMixing mixing(*gamut);
    Rng rng(5, 0);
    double simple = 0, inverse = 0, worstInverse = 0;
    const int n = 200;
    for (int k = 0; k < n; ++k) {
        const RGB target = gamut->reflectance(randomMixture(rng));
        const Lab wanted = labFromLinearSrgb(target);
        simple += ciede2000(gamut->colour(fractionsForColor(target)), wanted) / n;
        const double e = ciede2000(gamut->colour(mixing(target)), wanted);
        inverse += e / n;
        worstInverse = std::max(worstInverse, e);
    }
    std::printf("printed colour against the colour asked for (mean CIEDE2000, bundled resins): simple model %.2f, "
                "the gamut's inverse %.3f (worst %.3f)\n",
                simple, inverse, worstInverse);
    EXPECT_LT(worstInverse, 0.3);
    EXPECT_GT(simple, 10 * inverse);
    // The same colour, the same mixture (remembered).
    const RGB c{0.3f, 0.4f, 0.2f};
    EXPECT_EQ(mixing(c), mixing(c));
}

TEST(PrinterGamut, FileRoundTripAndKey) {
    const PrinterGamut gamut = gamutOf(2, curvedReflectance);
    const auto dir = test::freshTempDir("gamut_io");
    writePrinterGamut(gamut, "0123456789abcdef", "{\"levels\": 2}", dir / "g.json");
    EXPECT_FALSE(readPrinterGamut(dir / "g.json", "fedcba9876543210"));
    const auto read = readPrinterGamut(dir / "g.json", "0123456789abcdef");
    ASSERT_TRUE(read);
    EXPECT_EQ(read->gridReflectance(), gamut.gridReflectance());
    EXPECT_FALSE(readPrinterGamut(dir / "none.json", ""));
    std::ofstream(dir / "bad.json") << "{\"format\": \"something else\"}";
    EXPECT_THROW(readPrinterGamut(dir / "bad.json", ""), std::exception);
}

// Small characterisation settings for tests: 0.1 mm voxels on a 3 mm cube.
CharacterisationSettings smallSettings(int levels) {
    CharacterisationSettings s;
    s.levels = levels;
    s.voxel_mm = {0.1f, 0.1f, 0.1f};
    s.cube_mm = 3.0f;
    s.measuredSquare_mm = 1.0f;
    s.shellDepth_mm = 0.5f;
    s.spp = 8;
    return s;
}

// Each characterised colour against an independent render of the same
// mixture: the same halftone in a box scene built apart, printpt instead
// of volpath, another seed, every surface voxel rendered and the face
// centres averaged. They agree within their combined standard errors.
TEST(PrinterCharacterisation, AgreesWithIndependentRenders) {
    const MaterialTable materials = loadMaterials(test::sourceDir() / "data/materials/resins_illustrative.json");
    const CharacterisationSettings s = smallSettings(1);
    const PrinterGamut gamut = characterisePrinter(materials, s);
    const auto mixtures = PrinterGamut::gridMixtures(1);
    const Vec3i res{30, 30, 30};
    double chi2 = 0;
    int values = 0;
    for (size_t k = 0; k < mixtures.size(); ++k) {
        std::vector<Label> labels(size_t(res.x) * res.y * res.z, kWhiteLabel);
        halftoneFrame(
            res,
            [&](size_t i, MaterialFractions& f) {
                const int x = int(i % 30), y = int((i / 30) % 30), z = int(i / 900);
                const int d = std::min({x, 29 - x, y, 29 - y, z, 29 - z});
                f = mixtures[k];
                return d * 0.1f <= s.shellDepth_mm;
            },
            [&](size_t i, int m) { labels[i] = kPrintMaterialLabel[m]; });
        const Scene scene = test::boxScene(
            res, s.voxel_mm, [&](const Vec3i& v) { return labels[(size_t(v.z) * 30 + v.y) * 30 + v.x]; }, materials,
            s.ior);
        const LabelGrid& g = scene.medium->grid();
        const SurfaceVoxelSensor sensor(*scene.geometry, g.frame(), g.surfaceVoxels(), SurfaceVoxelSensor::Footprint::Patch);
        RenderSettings rs;
        rs.integrator = "printpt";
        rs.spp = 4;
        rs.seed = 1234;
        const RenderResult r = render(scene, sensor, rs);
        double sum[3] = {0, 0, 0}, var[3] = {0, 0, 0};
        int n = 0;
        for (size_t p = 0; p < sensor.pixelCount(); ++p) {
            const auto& px = sensor.pixels()[p];
            const float q[3] = {px.surfacePoint_mm.x, px.surfacePoint_mm.y, px.surfacePoint_mm.z};
            int onFace = 0, central = 0;
            for (int a = 0; a < 3; ++a) {
                onFace += q[a] < 0.01f || q[a] > 2.99f;
                central += std::abs(q[a] - 1.5f) <= 0.5f;
            }
            if (onFace != 1 || central != 2) continue;
            for (int c = 0; c < 3; ++c) {
                sum[c] += r.film.mean(p, c);
                var[c] += double(r.film.standardError(p, c)) * r.film.standardError(p, c);
            }
            ++n;
        }
        for (int c = 0; c < 3; ++c) {
            const double mean = sum[c] / n, se = std::sqrt(var[c]) / n;
            const double ours = gamut.gridReflectance()[k][size_t(c)], ourSe = gamut.gridStandardError()[k][size_t(c)];
            const double z = (ours - mean) / std::sqrt(se * se + ourSe * ourSe);
            std::printf("mixture %zu channel %d: characterised %.4f +- %.4f, independent %.4f +- %.4f (z %.2f)\n", k, c,
                        ours, ourSe, mean, se, z);
            EXPECT_LT(std::abs(z), 4.0) << "mixture " << k << " channel " << c;
            chi2 += z * z;
            ++values;
        }
    }
    EXPECT_LT(chi2 / values, 2.5);
}

// Made on first use, kept in the cache, read back the next time; another
// material table has another key.
TEST(PrinterCharacterisation, IsCachedByTheMaterialTablesContents) {
    const auto dir = test::freshTempDir("gamut_cache");
    const char* old = std::getenv("XDG_CACHE_HOME");
    const std::string saved = old ? old : "";
    ::setenv("XDG_CACHE_HOME", (dir / "cache").c_str(), 1);
    std::filesystem::copy_file(test::sourceDir() / "data/materials/resins_illustrative.json", dir / "m.json");
    const CharacterisationSettings s = smallSettings(1);
    std::vector<std::string> said;
    const PrinterGamut made = printerGamutFor(dir / "m.json", s, [&](const std::string& l) { said.push_back(l); });
    const PrinterGamut read = printerGamutFor(dir / "m.json", s, [&](const std::string& l) { said.push_back(l); });
    if (old) ::setenv("XDG_CACHE_HOME", saved.c_str(), 1);
    else ::unsetenv("XDG_CACHE_HOME");
    ASSERT_EQ(said.size(), 2u);
    EXPECT_NE(said[0].find("characterised 5 mixtures"), std::string::npos) << said[0];
    EXPECT_NE(said[1].find((dir / "cache" / "printlight").string()), std::string::npos) << said[1];
    EXPECT_EQ(made.gridReflectance(), read.gridReflectance());
    MaterialTable other = loadMaterials(dir / "m.json");
    const std::string key = characterisationKey(other, s);
    other.byLabel[kCyanLabel].albedo[0] = 0.3f;
    EXPECT_NE(characterisationKey(other, s), key);
    CharacterisationSettings finer = s;
    finer.levels = 2;
    EXPECT_NE(characterisationKey(loadMaterials(dir / "m.json"), finer), key);
}

// The loop on a uniform colour inside the gamut, on a 4 mm white cube at
// 0.1 mm voxels: from 37 CIEDE2000 (white) the faces' centres, far from the
// edges, end on average within 1.2 of the colour and each within 2 (their
// means rendered apart at 64 spp: the noise of such a mean is a few
// hundredths, so this is the print's own error); no iteration makes the
// score worse than the one before by more than that prediction's noise.
// What is left (0.35-1.35 per face) is a bias per face that the loop's
// noise hides from it: with 0.1 mm voxels its wide error still varies by
// 1-2 between iterations at 32 spp.
TEST(AppearanceLoop, ConvergesOnAUniformColourInsideTheGamut) {
    namespace fs = std::filesystem;
    const fs::path dir = test::freshTempDir("loop_uniform");
    writeObj(test::boxMesh({0, 0, 0}, {4, 4, 4}), dir / "cube.obj");
    writeLabelGridBin(test::boxGrid({40, 40, 40}, {0.1f, 0.1f, 0.1f}, [](const Vec3i&) { return Label(kWhiteLabel); }),
                      dir / "grid.bin");
    fs::copy_file(test::sourceDir() / "data/materials/resins_illustrative.json", dir / "materials.json");
    std::ofstream(dir / "scene.json") << R"({"object": {"mesh": "cube.obj", "labels": "grid.bin", "materials": "materials.json"},
        "sensor": {"type": "surface_voxels"},
        "render": {"integrator": "volpath", "spp": 32, "seed": 3, "channel": "rgb", "reentry": false}})";
    auto predictor = Predictor::fromSceneFile(dir / "scene.json");
    CharacterisationSettings cs = smallSettings(2);
    cs.cube_mm = 4.0f;
    cs.shellDepth_mm = 1.0f;
    const PrinterGamut gamut = characterisePrinter(loadMaterials(dir / "materials.json"), cs);
    // A muted colour the printer shows: a mixture's own colour.
    const RGB colour = gamut.reflectance({0.15f, 0.1f, 0.2f, 0.05f, 0.5f});
    OptimizeSettings os;
    os.maxIterations = 10;
    const OptimizeResult r =
        optimizeAppearance(*predictor, gamut, std::vector<RGB>(predictor->surfaceVoxelCount(), colour), os, {});
    for (const OptimizeIteration& it : r.iterations)
        std::printf("iteration %d: %.3f over the footprint (noise %.3f)\n", it.iteration, it.meanDeltaE, it.noiseDeltaE);
    EXPECT_LT(r.mappingLoss.meanFiltered, 0.05);  // inside the gamut: the identity
    EXPECT_GT(r.iterations.front().meanDeltaE, 10.0);  // the white cube it started from
    for (size_t i = 2; i < r.iterations.size(); ++i)
        EXPECT_LT(r.iterations[i].meanDeltaE, r.iterations[i - 1].meanDeltaE + r.iterations[i].noiseDeltaE) << i;
    // The best labels (the predictor holds them), rendered apart.
    predictor->settings().spp = 64;
    predictor->settings().seed = 99;
    const SurfacePrediction judged = predictor->predict();
    const std::vector<Point3f> points = predictor->surfacePoints_mm();
    double faces = 0;  // mean CIEDE2000 of the six centres
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            double sum[3] = {0, 0, 0};
            int count = 0;
            for (size_t i = 0; i < points.size(); ++i) {
                const float q[3] = {points[i].x, points[i].y, points[i].z};
                if (std::abs(q[axis] - 4.0f * side) > 0.01f) continue;
                bool central = true;
                for (int a = 0; a < 3; ++a)
                    if (a != axis && std::abs(q[a] - 2.0f) > 1.0f) central = false;
                if (!central) continue;
                for (int c = 0; c < 3; ++c) sum[c] += judged.radiance[i][size_t(c)];
                ++count;
            }
            ASSERT_GT(count, 300);
            const RGB mean{float(sum[0] / count), float(sum[1] / count), float(sum[2] / count)};
            const double dE = ciede2000(labFromLinearSrgb(mean), labFromLinearSrgb(colour));
            std::printf("face %d%c: centre %.4f %.4f %.4f against %.4f %.4f %.4f: CIEDE2000 %.3f\n", axis,
                        side ? '+' : '-', mean[0], mean[1], mean[2], colour[0], colour[1], colour[2], dE);
            EXPECT_LT(dE, 2.0) << "face " << axis << (side ? "+" : "-");
            faces += dE / 6;
        }
    EXPECT_LT(faces, 1.2);
}

}  // namespace
}  // namespace pl
