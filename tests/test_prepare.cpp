// printlight prepare: voxel volumes, signed distances and normals against
// analytic shapes; halftone fractions; readable errors for bad models.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <fstream>

#include "io/grid_io.h"
#include "io/image_io.h"
#include "core/input_error.h"
#include "io/mesh_io.h"
#include "prepare/halftone.h"
#include "prepare/prepare_model.h"
#include "prepare/voxelizer.h"
#include "test_util.h"

namespace pl {
namespace {

// Latitude-longitude sphere, outward winding.
TriangleMesh sphereMesh(const Point3f& c, float r, int rings, int segments) {
    TriangleMesh m;
    m.positions_mm.push_back(c + Vec3f(0, 0, -r));
    for (int i = 1; i < rings; ++i) {
        float theta = kPi * float(i) / rings;
        for (int j = 0; j < segments; ++j) {
            float phi = 2 * kPi * float(j) / segments;
            m.positions_mm.push_back(c + Vec3f(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), -std::cos(theta)) * r);
        }
    }
    m.positions_mm.push_back(c + Vec3f(0, 0, r));
    auto at = [&](int i, int j) { return uint32_t(1 + (i - 1) * segments + (j % segments)); };
    uint32_t top = uint32_t(m.positions_mm.size() - 1);
    for (int j = 0; j < segments; ++j) {
        m.indices.insert(m.indices.end(), {0, at(1, j + 1), at(1, j)});
        m.indices.insert(m.indices.end(), {top, at(rings - 1, j), at(rings - 1, j + 1)});
        for (int i = 1; i + 1 < rings; ++i)
            m.indices.insert(m.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
    validateClosedMesh(m, "sphere");
    return m;
}

struct VoxelStats {
    uint64_t inside = 0, members = 0;
    double maxSdfError = 0, maxNormalAngle_deg = 0;
    uint64_t bandChecked = 0;
};

// Voxelises and compares band samples with an exact distance and gradient.
VoxelStats voxelize(const Geometry& g, const VoxelizeSettings& s,
                    const std::function<float(const Point3f&)>& exactSdf,
                    const std::function<Vec3f(const Point3f&)>& exactNormal) {
    Voxelizer vox(g, s);
    VoxelStats st;
    for (int z = 0; z < vox.frame().resolution.z; ++z) {
        auto rows = vox.slice(z);
        for (int y = 0; y < int(rows.size()); ++y)
            for (const VoxelSample& v : rows[size_t(y)].samples) {
                st.inside += v.inside;
                st.members += v.member;
                if (!v.inBand) continue;
                Point3f c = vox.frame().voxelCenter_mm({v.x, y, z});
                st.maxSdfError = std::max(st.maxSdfError, double(std::abs(v.sdf_mm - exactSdf(c))));
                if (std::abs(v.sdf_mm) > 0.05f) {  // gradients are ill-defined at the surface itself
                    Vec3f n = exactNormal(c);
                    double angle = std::acos(std::clamp(double(dot(n, v.normal)), -1.0, 1.0)) * 180 / kPi;
                    st.maxNormalAngle_deg = std::max(st.maxNormalAngle_deg, angle);
                }
                ++st.bandChecked;
            }
    }
    return st;
}

TEST(Voxelizer, SphereVolumeDistanceAndNormals) {
    const Point3f c{1.3f, -0.7f, 2.1f};
    const float r = 2.0f;
    Geometry g(sphereMesh(c, r, 96, 192));
    VoxelizeSettings s;
    s.band_mm = 0.5f;
    VoxelStats st = voxelize(
        g, s, [&](const Point3f& p) { return length(p - c) - r; },
        [&](const Point3f& p) { return normalize(p - c); });
    double voxelVolume = double(s.voxel_mm.x) * s.voxel_mm.y * s.voxel_mm.z;
    double analytic = 4.0 / 3.0 * kPi * r * r * r;
    EXPECT_NEAR(st.inside * voxelVolume, analytic, 0.01 * analytic);
    EXPECT_GT(st.members, st.inside);  // the conservative fill adds the cut voxels
    // Facets deviate from the sphere by r (1 - cos(pi / 192)) ~ 0.27 um.
    EXPECT_GT(st.bandChecked, 100000u);
    EXPECT_LT(st.maxSdfError, 2e-3);
    EXPECT_LT(st.maxNormalAngle_deg, 3.0);
}

TEST(Voxelizer, CubeVolumeAndDistance) {
    const Vec3f lo{0.25f, 0.5f, 0.75f}, hi{10.25f, 10.5f, 10.75f};
    Geometry g(test::boxMesh(lo, hi));
    VoxelizeSettings s;
    s.band_mm = 0.15f;
    auto boxSdf = [&](const Point3f& p) {
        float out2 = 0, in = -1e30f;
        for (int a = 0; a < 3; ++a) {
            float d = std::max(lo[a] - p[a], p[a] - hi[a]);
            if (d > 0) out2 += d * d;
            in = std::max(in, d);
        }
        return out2 > 0 ? std::sqrt(out2) : in;
    };
    VoxelStats st = voxelize(g, s, boxSdf, [](const Point3f&) { return Vec3f(1, 0, 0); });
    double voxelVolume = double(s.voxel_mm.x) * s.voxel_mm.y * s.voxel_mm.z;
    double analytic = 1000.0;
    EXPECT_NEAR(st.inside * voxelVolume, analytic, 0.01 * analytic);
    EXPECT_LT(st.maxSdfError, 1e-4);
    // Exactly the voxels whose centre lies inside the box, axis by axis.
    Voxelizer vox(g, s);
    uint64_t expected = 1;
    for (int a = 0; a < 3; ++a) {
        uint64_t n = 0;
        for (int i = 0; i < vox.frame().resolution[a]; ++i) {
            float c = vox.frame().cornerMin_mm[a] + (i + 0.5f) * vox.frame().voxelSize_mm[a];
            n += c > lo[a] && c < hi[a];
        }
        expected *= n;
    }
    EXPECT_EQ(st.inside, expected);
}

TEST(Halftone, ReproducesConstantFractionsOnALargeBlock) {
    const int n = 64;
    for (RGB color : {RGB{0.6f, 0.3f, 0.8f}, RGB{0.9f, 0.85f, 0.2f}, RGB{0.15f, 0.5f, 0.45f}}) {
        MaterialFractions target = fractionsForColor(color);
        float sum = 0;
        for (float f : target) sum += f;
        ASSERT_NEAR(sum, 1.0f, 1e-6f);
        ErrorDiffusionHalftoner h(n, n);
        std::vector<MaterialFractions> targets(size_t(n) * n, target);
        std::vector<uint8_t> active(targets.size(), 1), chosen;
        std::array<double, kPrintMaterials> counts{};
        for (int z = 0; z < n; ++z) {
            h.halftoneSlice(z, targets, active, chosen);
            for (uint8_t m : chosen) counts[m] += 1;
        }
        for (int m = 0; m < kPrintMaterials; ++m)
            EXPECT_NEAR(counts[size_t(m)] / (double(n) * n * n), target[size_t(m)], 0.01) << "material " << m;
    }
}

TEST(Halftone, MixingModelCornerCases) {
    auto f = fractionsForColor({1, 1, 1});
    EXPECT_FLOAT_EQ(f[4], 1.0f);
    f = fractionsForColor({0, 0, 0});
    EXPECT_FLOAT_EQ(f[3], 1.0f);
    f = fractionsForColor({0, 1, 1});  // cyan
    EXPECT_FLOAT_EQ(f[0], 1.0f);
}

TEST(SurfaceColors, TexturedGltfRoundTripsToTheRightTexels) {
    auto dir = test::freshTempDir("gltf_texture");
    // A 2 x 2 texture: red, green / blue, white (top row first).
    Texture tex;
    tex.width = tex.height = 2;
    tex.linear = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
    writeTexturePng(tex, dir / "tex.png");
    // One unit square face of a box gets the whole texture; the rest (0, 0).
    TriangleMesh box = test::boxMesh({0, 0, 0}, {1, 1, 1});
    SurfaceAppearance look;
    look.materials.push_back({{1, 1, 1}, 0});
    look.uvs.assign(box.positions_mm.size(), {0.25f, 0.25f});
    for (size_t i = 0; i < box.positions_mm.size(); ++i) {
        const Point3f& p = box.positions_mm[i];
        look.uvs[i] = {p.x, 1.0f - p.y};  // the z faces map x -> u, y -> up
    }
    writeGltf(box, look, "tex.png", dir / "box.gltf");
    MeshAsset asset = loadMeshAsset(dir / "box.gltf");
    ASSERT_EQ(asset.appearance.textures.size(), 1u);
    Geometry g(std::move(asset.mesh));
    // Points on the top face (z = 1) at the texel centres.
    struct Probe { Point3f p; RGB expected; };
    const Probe probes[] = {{{0.25f, 0.75f, 1}, {1, 0, 0}}, {{0.75f, 0.75f, 1}, {0, 1, 0}},
                            {{0.25f, 0.25f, 1}, {0, 0, 1}}, {{0.75f, 0.25f, 1}, {1, 1, 1}}};
    for (const Probe& pr : probes) {
        auto hit = g.intersect({pr.p + Vec3f(0, 0, 1), {0, 0, -1}});
        ASSERT_TRUE(hit);
        RGB c = asset.appearance.colorAt(g.mesh(), hit->prim, hit->p);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], pr.expected[k], 2e-3f) << pr.p.x << "," << pr.p.y;
    }
}

// Exit code of a printlight run; its stderr goes to err.
int prepareExit(const std::string& args, std::string& err) {
    auto dir = test::freshTempDir("prepare_cli_out");
    test::CliRun r = test::runPrintlight(args, dir);
    err = r.err;
    return r.exitCode;
}
// prepare as a library call: a 2 mm cube in one colour becomes a printed
// block whose 0.3 mm shell holds that colour's halftone and whose inside
// is white, with void around it; a grid too large is refused before any
// allocation, with a PrepareError.
TEST(PrepareModel, ABoxInOneColourHasAHalftonedShellAndAWhiteCore) {
    Geometry box(synthetic::boxMesh({0, 0, 0}, {2, 2, 2}));
    PrepareSettings settings;
    settings.voxel_mm = {0.1f, 0.1f, 0.1f};
    settings.extrude_mm = 0.3f;
    settings.color = RGB{0.9f, 0.2f, 0.2f};
    PreparedModel p = prepareModel(box, SurfaceAppearance{}, settings);
    EXPECT_EQ(p.colorSource, "constant --color");
    // 20 voxels a side, or 21 where the faces cross voxels (conservative
    // fill); the shell is 3 voxels deep.
    EXPECT_GE(p.printedVoxels, 20u * 20u * 20u);
    EXPECT_LE(p.printedVoxels, 21u * 21u * 21u);
    const uint64_t core = p.printedVoxels - p.shellVoxels;
    EXPECT_TRUE(core == 14u * 14u * 14u || core == 15u * 15u * 15u) << core;
    const auto hist = p.labels.histogram();
    EXPECT_GE(hist[kWhiteLabel], core);
    EXPECT_GT(hist[kMagentaLabel] + hist[kYellowLabel], 0u);  // red: magenta and yellow
    EXPECT_GT(hist[kVoidLabel], 0u);                          // the margin
    const GridFrame& f = p.labels.frame();
    const Vec3i centre{f.indexMin.x + f.resolution.x / 2, f.indexMin.y + f.resolution.y / 2,
                       f.indexMin.z + f.resolution.z / 2};
    EXPECT_EQ(p.labels.label(centre), kWhiteLabel);
    settings.voxel_mm = {1e-4f, 1e-4f, 1e-4f};
    EXPECT_THROW(prepareModel(box, SurfaceAppearance{}, settings), PrepareError);
}

// --band-mm: the sdf/normal band written is as wide as asked (the shell
// and labels do not change); 0 writes no sdf/normal grids.
TEST(PrepareModel, TheDistanceBandIsAsWideAsAsked) {
    Geometry box(synthetic::boxMesh({0, 0, 0}, {2, 2, 2}));
    PrepareSettings settings;
    settings.voxel_mm = {0.1f, 0.1f, 0.1f};
    settings.extrude_mm = 0.3f;
    const PreparedModel full = prepareModel(box, SurfaceAppearance{}, settings);
    settings.fieldBand_mm = 0.15f;
    const PreparedModel narrow = prepareModel(box, SurfaceAppearance{}, settings);
    settings.fieldBand_mm = 0.0f;
    const PreparedModel none = prepareModel(box, SurfaceAppearance{}, settings);
    EXPECT_GT(full.bandVoxels, narrow.bandVoxels);
    EXPECT_GT(narrow.bandVoxels, 0u);
    EXPECT_EQ(none.bandVoxels, 0u);
    EXPECT_EQ(full.labels.histogram(), none.labels.histogram());
    // Voxel centres within 0.15 mm of the faces: the outer layer (0.05 mm
    // in) and the one outside it, 20 x 20 on each of 6 faces, and more.
    EXPECT_GE(narrow.bandVoxels, 2u * 6u * 20u * 20u);
    const GridFrame& f = narrow.labels.frame();
    for (int x = f.indexMin.x; x < f.indexMin.x + f.resolution.x; ++x) {
        const Vec3i v{x, f.indexMin.y + f.resolution.y / 2, f.indexMin.z + f.resolution.z / 2};
        const float trueDistance_mm = std::min(f.voxelCenter_mm(v).x, 2.0f - f.voxelCenter_mm(v).x);
        if (std::abs(trueDistance_mm) <= 0.149f) {
            EXPECT_NEAR(narrow.fields.sdf(v), -trueDistance_mm, 1e-4f) << x;
        }
    }
    auto dir = test::freshTempDir("prepare_band");
    writePreparedVdb(none.labels, none.fields, dir / "none.vdb");
    EXPECT_EQ(loadVoxelFields(dir / "none.vdb", none.labels.frame()), nullptr);
    writePreparedVdb(narrow.labels, narrow.fields, dir / "narrow.vdb");
    EXPECT_NE(loadVoxelFields(dir / "narrow.vdb", narrow.labels.frame()), nullptr);
    std::filesystem::remove_all(dir);
}

TEST(PrepareCli, MissingTexturesKeepKdUnreadableOnesAndOpenMeshesFailCleanly) {
    auto dir = test::freshTempDir("prepare_cli");
    // OBJ whose material names a texture that is not there.
    std::ofstream(dir / "cube.mtl") << "newmtl skin\nKd 1 1 1\nmap_Kd missing.png\n";
    std::ofstream obj(dir / "cube.obj");
    obj << "mtllib cube.mtl\nusemtl skin\n";
    TriangleMesh box = test::boxMesh({0, 0, 0}, {1, 1, 1});
    for (const auto& p : box.positions_mm) obj << "v " << p.x << ' ' << p.y << ' ' << p.z << '\n';
    for (size_t t = 0; t < box.triangleCount(); ++t)
        obj << "f " << box.indices[3 * t] + 1 << ' ' << box.indices[3 * t + 1] + 1 << ' ' << box.indices[3 * t + 2] + 1 << '\n';
    obj.close();
    std::string err;
    // A texture that is not there: the material keeps its Kd, and a warning names the file.
    EXPECT_EQ(prepareExit("prepare " + (dir / "cube.obj").string() + " -o " + (dir / "kd.vdb").string() + " --voxel 0.1,0.1,0.1",
                          err),
              0);
    EXPECT_NE(err.find("warning:"), std::string::npos) << err;
    EXPECT_NE(err.find("missing.png not found"), std::string::npos) << err;
    // Windows' separator (".\\name.png", as exporters there write it) is ours.
    std::ofstream(dir / "cube.mtl") << "newmtl skin\nKd 1 1 1\nmap_Kd .\\missing.png\n";
    // A texture file that is not an image: refused, naming it.
    std::ofstream(dir / "missing.png") << "not a png";
    EXPECT_EQ(prepareExit("prepare " + (dir / "cube.obj").string() + " -o " + (dir / "out.vdb").string(), err), 1);
    EXPECT_NE(err.find("missing.png"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    // An open mesh.
    box.indices.resize(box.indices.size() - 3);
    writeObj(box, dir / "open.obj");
    EXPECT_EQ(prepareExit("prepare " + (dir / "open.obj").string() + " -o " + (dir / "out.vdb").string(), err), 1);
    EXPECT_NE(err.find("not closed"), std::string::npos) << err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out.vdb"));
}

TEST(PrepareCli, WritesLabelsSdfAndNormalsThatReadBack) {
    auto dir = test::freshTempDir("prepare_ok");
    writeObj(test::boxMesh({0, 0, 0}, {2, 1.5f, 1}), dir / "box.obj");
    std::string err;
    ASSERT_EQ(prepareExit("prepare " + (dir / "box.obj").string() + " -o " + (dir / "box.vdb").string() +
                                " --color 0.2,0.6,0.9 --extrude-mm 0.2 --keep-colors --quiet",
                            err),
              0)
        << err;
    LabelGrid grid = loadLabelGrid(dir / "box.vdb", std::nullopt);
    auto hist = grid.histogram();
    EXPECT_GT(hist[0], 0u);  // cyan for a bluish target
    EXPECT_GT(hist[4], 0u);  // white inside and in the mix
    EXPECT_EQ(grid.voidLabel(), 5);
    // The surface voxels of the prepared grid sit on the box.
    for (const SurfaceVoxel& sv : grid.surfaceVoxels()) {
        Point3f c = grid.frame().voxelCenter_mm(sv.voxel);
        float dOut = 0;
        for (int a = 0; a < 3; ++a) dOut = std::max(dOut, std::max(-c[a], c[a] - (a == 0 ? 2.0f : a == 1 ? 1.5f : 1.0f)));
        ASSERT_LT(dOut, 0.5f * 0.0847f + 1e-4f);
    }
}

}  // namespace
}  // namespace pl
