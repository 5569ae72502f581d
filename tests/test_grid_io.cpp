// Label grids round-trip unchanged through .vdb, LabelGrid .bin/.gz and
// Mitsuba .vol; corrupt files give clear errors.
#include <gtest/gtest.h>

#include <fstream>

#include "core/rng.h"
#include "io/grid_io.h"
#include "media/voxel_int_grid.h"
#include "core/input_error.h"
#include "io/materials_io.h"
#include "io/mesh_io.h"
#include "io/mesh_repair.h"
#include "test_util.h"

namespace pl {
namespace {

LabelGrid randomGrid() {
    Rng rng(17, 3);
    GridFrame f;
    f.resolution = {37, 21, 50};
    f.voxelSize_mm = kPrinterVoxel_mm;
    f.cornerMin_mm = {-1.5f, 2.25f, 0.5f};
    std::vector<Label> labels(f.voxelCount());
    for (size_t i = 0; i < labels.size(); ++i) {
        // Blocks of one label (tiles after pruning) and noisy voxels.
        uint32_t block = (uint32_t(i % 37) / 16) + 3 * (uint32_t(i / (37 * 21)) / 16);
        labels[i] = (rng.uniform() < 0.7f) ? Label(block % 7) : Label(rng.next32() % 7);
    }
    return LabelGrid::fromDense(f, labels, 5);
}

void expectSameGrid(const LabelGrid& a, const LabelGrid& b) {
    EXPECT_EQ(a.frame().resolution, b.frame().resolution);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(a.frame().voxelSize_mm[k], b.frame().voxelSize_mm[k], 1e-6f);
        EXPECT_NEAR(a.frame().cornerMin_mm[k], b.frame().cornerMin_mm[k], 1e-5f);
    }
    EXPECT_EQ(a.voidLabel(), b.voidLabel());
    EXPECT_EQ(a.toDense(), b.toDense());
    EXPECT_EQ(a.histogram(), b.histogram());
}

TEST(GridIo, RoundTripsThroughEveryFormat) {
    auto dir = test::freshTempDir("grid_io");
    LabelGrid grid = randomGrid();
    for (const char* name : {"g.vdb", "g.bin", "g.gz", "g.vol"}) {
        auto path = dir / name;
        if (path.extension() == ".vdb") writeLabelGridVdb(grid, path);
        else if (path.extension() == ".vol") writeLabelGridVol(grid, path);
        else writeLabelGridBin(grid, path);
        SCOPED_TRACE(name);
        expectSameGrid(grid, loadLabelGrid(path, std::nullopt));
    }
}

TEST(GridIo, SparseTreeIsMuchSmallerThanDenseFloats) {
    GridFrame f;
    f.resolution = {128, 64, 128};
    std::vector<Label> labels(f.voxelCount(), 4);
    LabelGrid grid = LabelGrid::fromDense(f, labels, 5);
    // A uniform block collapses into tiles: only the fixed-size internal
    // nodes remain (a 32^3-entry upper node is ~300 kB on its own).
    EXPECT_LT(grid.memoryBytes() * 40, f.voxelCount() * 16);
    EXPECT_EQ(grid.histogram()[4], f.voxelCount());
}

void writeBytes(const std::filesystem::path& p, const std::string& bytes) {
    std::ofstream(p, std::ios::binary) << bytes;
}

void expectInputError(const std::function<void()>& f, const std::string& needle) {
    try {
        f();
        ADD_FAILURE() << "no error; expected one mentioning '" << needle << "'";
    } catch (const InputError& e) {
        std::string msg = e.what();
        EXPECT_NE(msg.find(needle), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << "multi-line message: " << msg;
    }
}

TEST(GridIo, CorruptFilesGiveClearErrors) {
    auto dir = test::freshTempDir("grid_io_bad");
    LabelGrid grid = randomGrid();
    writeLabelGridBin(grid, dir / "ok.bin");
    std::ifstream in(dir / "ok.bin", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    writeBytes(dir / "truncated.bin", bytes.substr(0, bytes.size() - 100));
    expectInputError([&] { loadLabelGrid(dir / "truncated.bin", std::nullopt); }, "truncated");
    writeBytes(dir / "trailing.bin", bytes + "xyz");
    expectInputError([&] { loadLabelGrid(dir / "trailing.bin", std::nullopt); }, "trailing");
    std::string absurd = bytes;
    int32_t huge[3] = {1 << 20, 1 << 20, 1 << 20};
    absurd.replace(0, 12, reinterpret_cast<const char*>(huge), 12);
    writeBytes(dir / "absurd.bin", absurd);
    expectInputError([&] { loadLabelGrid(dir / "absurd.bin", std::nullopt); }, "too large");
    int32_t negative[3] = {-4, 10, 10};
    absurd.replace(0, 12, reinterpret_cast<const char*>(negative), 12);
    writeBytes(dir / "negative.bin", absurd);
    expectInputError([&] { loadLabelGrid(dir / "negative.bin", std::nullopt); }, "absurd resolution");
    writeBytes(dir / "notgzip.gz", "this is not gzip at all, nor long enough");
    expectInputError([&] { loadLabelGrid(dir / "notgzip.gz", std::nullopt); }, "notgzip.gz");
    writeBytes(dir / "bad.vol", "VOX\x03 and more bytes here");
    expectInputError([&] { loadLabelGrid(dir / "bad.vol", std::nullopt); }, "not a Mitsuba VOL");
    writeBytes(dir / "bad.vdb", "definitely not a vdb file");
    expectInputError([&] { loadLabelGrid(dir / "bad.vdb", std::nullopt); }, "bad.vdb");
    expectInputError([&] { loadLabelGrid(dir / "missing.vdb", std::nullopt); }, "cannot open");
    expectInputError([&] { loadLabelGrid(dir / "grid.txt", std::nullopt); }, "cannot open");
    writeBytes(dir / "grid.txt", "x");
    expectInputError([&] { loadLabelGrid(dir / "grid.txt", std::nullopt); }, "unknown label grid format");
}

TEST(MeshIo, ObjAndGltfCubesAgree) {
    auto data = test::sourceDir() / "data/meshes";
    TriangleMesh obj = loadMesh(data / "cube10.obj"), gltf = loadMesh(data / "cube10.gltf");
    EXPECT_EQ(obj.triangleCount(), 12u);
    EXPECT_EQ(gltf.triangleCount(), 12u);
    Geometry a(std::move(obj)), b(std::move(gltf));
    for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(a.bounds().lo[k], b.bounds().lo[k]);
        EXPECT_EQ(a.bounds().hi[k], b.bounds().hi[k]);
    }
    Ray r{{5, 5, -3}, {0, 0, 1}};
    ASSERT_TRUE(a.intersect(r) && b.intersect(r));
    EXPECT_FLOAT_EQ(a.intersect(r)->t, 3.0f);
    EXPECT_FLOAT_EQ(b.intersect(r)->ng.z, -1.0f);  // outward normal of the bottom face
}

// STL (ASCII and binary, each facet with its own vertices) and PLY (shared
// vertices with colours) read through Assimp into the same closed box; a
// glTF 1.0 file is named as such.
TEST(MeshIo, StlAndPlyBoxesAndGltf1) {
    auto dir = test::freshTempDir("mesh_io_formats");
    const TriangleMesh box = test::boxMesh({0, 0, 0}, {1, 2, 3});
    std::ostringstream ascii;
    std::string binary(80, ' ');
    auto put = [&](const void* p, size_t n) { binary.append(static_cast<const char*>(p), n); };
    const uint32_t count = uint32_t(box.triangleCount());
    put(&count, 4);
    ascii << "solid box\n";
    for (size_t t = 0; t < box.triangleCount(); ++t) {
        const float normal[3] = {0, 0, 0};
        put(normal, 12);
        ascii << " facet normal 0 0 0\n  outer loop\n";
        for (int k = 0; k < 3; ++k) {
            const Point3f& p = box.positions_mm[box.indices[3 * t + k]];
            const float xyz[3] = {p.x, p.y, p.z};
            put(xyz, 12);
            ascii << "   vertex " << p.x << " " << p.y << " " << p.z << "\n";
        }
        ascii << "  endloop\n endfacet\n";
        const uint16_t attribute = 0;
        put(&attribute, 2);
    }
    ascii << "endsolid box\n";
    writeBytes(dir / "ascii.stl", ascii.str());
    writeBytes(dir / "binary.stl", binary);
    std::ostringstream ply;
    ply << "ply\nformat ascii 1.0\nelement vertex " << box.positions_mm.size()
        << "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
           "property uchar blue\nelement face "
        << box.triangleCount() << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const Point3f& p : box.positions_mm) ply << p.x << " " << p.y << " " << p.z << " 255 0 0\n";
    for (size_t t = 0; t < box.triangleCount(); ++t)
        ply << "3 " << box.indices[3 * t] << " " << box.indices[3 * t + 1] << " " << box.indices[3 * t + 2] << "\n";
    writeBytes(dir / "box.ply", ply.str());

    for (const char* name : {"ascii.stl", "binary.stl", "box.ply"}) {
        MeshAsset asset = loadMeshAsset(dir / name);
        EXPECT_EQ(asset.mesh.triangleCount(), 12u) << name;
        EXPECT_EQ(asset.mesh.positions_mm.size(), 8u) << name << ": vertices welded";
        Geometry g(std::move(asset.mesh));
        EXPECT_EQ(g.bounds().hi.z, 3.0f) << name;
        auto hit = g.intersect({{0.5f, 1, -1}, {0, 0, 1}});
        ASSERT_TRUE(hit) << name;
        EXPECT_FLOAT_EQ(hit->ng.z, -1.0f) << name;
        if (std::string(name) == "box.ply") {
            ASSERT_EQ(asset.appearance.vertexColors.size(), 8u);
            EXPECT_FLOAT_EQ(asset.appearance.vertexColors[0][0], 1.0f);
            EXPECT_FLOAT_EQ(asset.appearance.vertexColors[0][1], 0.0f);
        }
    }
    writeBytes(dir / "broken.stl", "solid x\n facet normal 0 0 1\n");
    expectInputError([&] { loadMesh(dir / "broken.stl"); }, "broken.stl");
    writeBytes(dir / "v1.gltf", R"({"asset": {"version": "1.0"}, "meshes": {"m": {}}})");
    expectInputError([&] { loadMesh(dir / "v1.gltf"); }, "glTF 1.0 is not supported");
    writeBytes(dir / "v1.glb", std::string("glTF\x01\0\0\0\x14\0\0\0", 12) + std::string(8, '\0'));
    expectInputError([&] { loadMesh(dir / "v1.glb"); }, "glTF 1.0 is not supported");
}

// Repair (CGAL): a box with a missing triangle, one triangle flipped and
// every vertex repeated per triangle (as STL stores it) comes back closed
// and oriented outwards, with the colours of the triangles it kept.
TEST(MeshIo, RepairClosesOrientsAndWelds) {
    auto dir = test::freshTempDir("mesh_repair");
    const TriangleMesh box = test::boxMesh({0, 0, 0}, {1, 2, 3});
    TriangleMesh soup;
    SurfaceAppearance look;
    for (size_t t = 0; t + 1 < box.triangleCount(); ++t)  // the last triangle left out: a hole
        for (int k = 0; k < 3; ++k) {
            const int corner = t == 0 ? 2 - k : k;  // the first triangle flipped
            soup.indices.push_back(uint32_t(soup.positions_mm.size()));
            soup.positions_mm.push_back(box.positions_mm[box.indices[3 * t + size_t(corner)]]);
            look.vertexColors.push_back(RGB{0.25f, 0.5f, 0.75f});
        }
    MeshRepairSummary summary;
    MeshAsset repaired = repairMesh(MeshAsset{soup, look}, "soup", summary);
    EXPECT_EQ(summary.weldedVertices, 33u - 8u);
    EXPECT_EQ(summary.holesFilled, 1u);
    EXPECT_EQ(summary.fillTriangles, 1u);
    EXPECT_EQ(summary.reorientedTriangles, 1u);
    ASSERT_EQ(repaired.mesh.triangleCount(), 12u);
    ASSERT_EQ(repaired.appearance.vertexColors.size(), 36u);
    for (const RGB& c : repaired.appearance.vertexColors) EXPECT_EQ(c, (RGB{0.25f, 0.5f, 0.75f}));
    // Closed and outward: rays from outside enter through outward faces
    // everywhere, including where the hole was and the flipped triangle is.
    Geometry g(std::move(repaired.mesh));
    for (const Ray& r : {Ray{{0.5f, 1, -1}, {0, 0, 1}}, Ray{{0.5f, 1, 4}, {0, 0, -1}}, Ray{{-1, 1, 1.5f}, {1, 0, 0}},
                         Ray{{2, 1, 1.5f}, {-1, 0, 0}}, Ray{{0.5f, -1, 1.5f}, {0, 1, 0}}, Ray{{0.5f, 3, 1.5f}, {0, -1, 0}}}) {
        auto hit = g.intersect(r);
        ASSERT_TRUE(hit) << r.o.x << " " << r.o.y << " " << r.o.z;
        EXPECT_LT(dot(hit->ng, r.d), 0.0f) << r.o.x << " " << r.o.y << " " << r.o.z;
    }
    // Loading: refused as it is, repaired on request.
    writeObj(soup, dir / "open.obj");
    expectInputError([&] { loadMesh(dir / "open.obj"); }, "not closed");
    EXPECT_EQ(loadMesh(dir / "open.obj", {}, true).triangleCount(), 12u);
}

TEST(MeshIo, OpenAndInvertedMeshes) {
    auto dir = test::freshTempDir("mesh_io");
    TriangleMesh box = test::boxMesh({0, 0, 0}, {1, 2, 3});
    TriangleMesh open = box;
    open.indices.resize(open.indices.size() - 3);
    writeObj(open, dir / "open.obj");
    expectInputError([&] { loadMesh(dir / "open.obj"); }, "not closed");
    // Inverted winding is repaired (outward normals), not rejected.
    TriangleMesh inverted = box;
    for (size_t t = 0; t < inverted.triangleCount(); ++t) std::swap(inverted.indices[3 * t + 1], inverted.indices[3 * t + 2]);
    writeObj(inverted, dir / "inverted.obj");
    Geometry g(loadMesh(dir / "inverted.obj"));
    auto hit = g.intersect({{0.5f, 1, -1}, {0, 0, 1}});
    ASSERT_TRUE(hit);
    EXPECT_FLOAT_EQ(hit->ng.z, -1.0f);
    writeBytes(dir / "garbage.obj", "v 1 2\nf 1 2 3\n");
    expectInputError([&] { loadMesh(dir / "garbage.obj"); }, "line 1");
    writeBytes(dir / "garbage.gltf", "{ not json");
    expectInputError([&] { loadMesh(dir / "garbage.gltf"); }, "malformed glTF");
}

TEST(MaterialsIo, ValidatesCoefficients) {
    auto dir = test::freshTempDir("materials_io");
    auto write = [&](const std::string& body) {
        writeBytes(dir / "m.json", body);
        return dir / "m.json";
    };
    MaterialTable t = loadMaterials(test::sourceDir() / "data/materials/resins_illustrative.json");
    EXPECT_TRUE(t.byLabel[4].defined);
    EXPECT_EQ(t.byLabel[4].sigmaT_perMm[2], 24.0f);
    EXPECT_EQ(t.byLabel[1].sigmaT_perMm[0], 2.5f);
    expectInputError([&] { loadMaterials(write(R"([{"label":1,"albedo":[1,1,1],"density":[-1,1,1]}])")); }, "must not be negative");
    expectInputError([&] { loadMaterials(write(R"([{"label":1,"albedo":[1,1,1],"density":[1,1,1],"anisotropy":[1,0,0]}])")); }, "|g| < 1");
    expectInputError([&] { loadMaterials(write(R"([{"label":1,"albedo":[1.2,1,1],"density":[1,1,1]}])")); }, "albedo");
    expectInputError([&] { loadMaterials(write(R"([{"label":1,"albedo":[1,1,1],"density":[NaN,1,1]}])")); }, "malformed JSON");
    expectInputError([&] { loadMaterials(write(R"([{"label":300,"albedo":1,"density":1}])")); }, "0..255");
    expectInputError([&] { loadMaterials(write(R"([{"label":1,"albedo":1,"desnity":1}])")); }, "desnity");
    expectInputError([&] { loadMaterials(write(R"([{"label":1,"albedo":1,"density":1},{"label":1,"albedo":1,"density":1}])")); }, "repeats");
}

}  // namespace
}  // namespace pl


namespace pl {
// Read through the cached accessor, a grid's labels are LabelGrid::label's,
// in and out of the frame.
TEST(LabelReader, ReadsWhatTheGridHolds) {
    const LabelGrid grid = randomGrid();
    const LabelReader reader(grid);
    const Vec3i& r = grid.frame().resolution;
    for (int z = -1; z <= r.z; ++z)
        for (int y = -1; y <= r.y; ++y)
            for (int x = -1; x <= r.x; ++x) ASSERT_EQ(reader.at({x, y, z}), grid.label({x, y, z})) << x << " " << y << " " << z;
}

// Sparse integers on voxels: what was set reads back, the rest is the
// background, every voxel set is visited once, and the memory follows the
// voxels set, not the volume they span (the optimisation loop's shell).
TEST(VoxelIntGrid, HoldsWhatWasSetSparsely) {
    VoxelIntGrid grid(-1);
    std::vector<Vec3i> set;
    for (int k = 0; k < 1000; ++k) set.push_back({k * 997 % 1000, k * 7919 % 1000, k * 104729 % 1000});
    for (size_t k = 0; k < set.size(); ++k) grid.set(set[k], int32_t(k));
    for (size_t k = 0; k < set.size(); ++k) EXPECT_EQ(grid.get(set[k]), int32_t(k));
    EXPECT_EQ(grid.get({5, 5, 6}), -1);
    EXPECT_EQ(grid.setCount(), set.size());
    size_t visited = 0;
    grid.forEachSet([&](const Vec3i& v, int32_t k) {
        EXPECT_EQ(set[size_t(k)], v);
        ++visited;
    });
    EXPECT_EQ(visited, set.size());
    // A box's surface, 300 voxels a side: a quarter of its dense volume at most.
    VoxelIntGrid shell(-1);
    const int n = 300;
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                if (x == 0 || y == 0 || z == 0 || x == n - 1 || y == n - 1 || z == n - 1) shell.set({x, y, z}, 1);
    EXPECT_LT(shell.memoryBytes(), uint64_t(n) * n * n * 4 / 4);
}

}  // namespace pl
