// make-test-data OUTDIR: writes the procedural test-set models (in the kind
// of Brecka 2021, table 3.1) as glTF with their textures. Everything is made
// here, deterministically; no third-party data.
//   cube10.gltf, cube20.gltf                 10 / 20 mm cubes, white
//   cube10_greek.gltf, cube20_greek.gltf     the same with a high-frequency meander texture (greek.png)
//   animal.gltf, animal_spotted.gltf         a thin, curvy seahorse-like tube ~5 x 12 x 13 mm, white / spotted (spots.png)
//   bone.gltf                                a ~44 mm bone-like shape with ~60k triangles (memory and scale)
//   cube10_clear.vdb                         labels for cube10.gltf: clear resin with a white 4 mm core and a
//                                            halftoned ring inlaid 0.1-0.6 mm under the top face (a clear
//                                            print with coloured inlays; prepare does not make clear prints)
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>

#include "core/rng.h"
#include "io/grid_io.h"
#include "io/image_io.h"
#include "io/mesh_io.h"
#include "media/label_grid.h"
#include "media/materials.h"

namespace {

using namespace pl;

// Cube [0, size]^3 with each face mapped onto the whole texture.
void cube(float size, TriangleMesh& mesh, SurfaceAppearance& look) {
    // Per face: origin corner and the two in-face axes (u, v), outward by u x v.
    struct Face { Vec3f o, u, v; };
    const Face faces[6] = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{0, 1, 0}, {0, -1, 0}, {0, 0, 1}},
                           {{1, 1, 0}, {-1, 0, 0}, {0, 0, 1}}, {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}},
                           {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 0}, {1, 0, 0}, {0, -1, 0}}};
    for (const Face& f : faces) {
        uint32_t base = uint32_t(mesh.positions_mm.size());
        for (int k = 0; k < 4; ++k) {
            float a = float(k & 1), b = float(k >> 1);
            mesh.positions_mm.push_back((f.o + f.u * a + f.v * b) * size);
            look.uvs.push_back({a, 1.0f - b});
        }
        mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 3, base, base + 3, base + 2});
    }
}

// The ellipsoid with these radii inscribed in [0, 2 radius]: a latitude-
// longitude mesh of 64 x 32 quads, within 0.01 mm of the true surface up
// to 12 mm across (finer meshes only slow light tracing's prism queries).
void ellipsoidMesh(const Vec3f& radius_mm, TriangleMesh& mesh, SurfaceAppearance& look) {
    const int rings = 32, segments = 64;
    auto vertex = [&](float theta, float phi) {
        mesh.positions_mm.push_back({radius_mm.x * (1 + std::sin(theta) * std::cos(phi)),
                                     radius_mm.y * (1 + std::sin(theta) * std::sin(phi)),
                                     radius_mm.z * (1 + std::cos(theta))});
        look.uvs.push_back({phi / (2 * kPi), theta / kPi});
        return uint32_t(mesh.positions_mm.size() - 1);
    };
    // Ring i (1 .. rings - 1) at polar angle pi i / rings; one vertex per pole.
    const uint32_t top = vertex(0, 0), first = uint32_t(mesh.positions_mm.size());
    for (int i = 1; i < rings; ++i)
        for (int j = 0; j < segments; ++j) vertex(kPi * float(i) / rings, 2 * kPi * float(j) / segments);
    const uint32_t bottom = vertex(kPi, 0);
    auto at = [&](int i, int j) { return first + uint32_t((i - 1) * segments + (j % segments)); };
    for (int j = 0; j < segments; ++j) {  // outward winding
        mesh.indices.insert(mesh.indices.end(), {top, at(1, j), at(1, j + 1)});
        mesh.indices.insert(mesh.indices.end(), {bottom, at(rings - 1, j + 1), at(rings - 1, j)});
        for (int i = 1; i + 1 < rings; ++i)
            mesh.indices.insert(mesh.indices.end(), {at(i, j), at(i + 1, j), at(i, j + 1),
                                                     at(i, j + 1), at(i + 1, j), at(i + 1, j + 1)});
    }
}

// A closed tube swept along a curve with rotation-minimising frames, a
// radius profile, poles at both ends; u runs along the curve, v around it.
void sweep(int rings, int segments, const std::function<Point3f(float)>& curve,
           const std::function<float(float, float)>& radius, TriangleMesh& mesh, SurfaceAppearance& look) {
    std::vector<Point3f> c(static_cast<size_t>(rings));
    for (int i = 0; i < rings; ++i) c[size_t(i)] = curve(float(i) / (rings - 1));
    Vec3f t0 = normalize(c[1] - c[0]);
    Vec3f n = normalize(cross(t0, std::abs(t0.x) < 0.9f ? Vec3f(1, 0, 0) : Vec3f(0, 1, 0)));
    std::vector<Vec3f> tangent(static_cast<size_t>(rings)), normal(static_cast<size_t>(rings));
    for (int i = 0; i < rings; ++i) {
        Vec3f t = normalize(c[size_t(std::min(i + 1, rings - 1))] - c[size_t(std::max(i - 1, 0))]);
        n = normalize(n - t * dot(n, t));  // transport the frame along the curve
        tangent[size_t(i)] = t;
        normal[size_t(i)] = n;
    }
    auto pole = [&](int i, float sign) {
        float s = float(i) / (rings - 1);
        mesh.positions_mm.push_back(c[size_t(i)] + tangent[size_t(i)] * (sign * radius(s, 0.0f)));
        look.uvs.push_back({s, 0.5f});
        return uint32_t(mesh.positions_mm.size() - 1);
    };
    uint32_t start = pole(0, -1.0f);
    uint32_t first = uint32_t(mesh.positions_mm.size());
    for (int i = 0; i < rings; ++i) {
        float s = float(i) / (rings - 1);
        Vec3f b = cross(tangent[size_t(i)], normal[size_t(i)]);
        for (int j = 0; j <= segments; ++j) {  // j = segments repeats j = 0 for the texture seam
            float phi = 2 * kPi * float(j % segments) / segments;
            float r = radius(s, phi);
            mesh.positions_mm.push_back(c[size_t(i)] + (normal[size_t(i)] * std::cos(phi) + b * std::sin(phi)) * r);
            look.uvs.push_back({s, float(j) / segments});
        }
    }
    uint32_t end = pole(rings - 1, 1.0f);
    auto at = [&](int i, int j) { return first + uint32_t(i * (segments + 1) + j); };
    for (int j = 0; j < segments; ++j) {
        mesh.indices.insert(mesh.indices.end(), {start, at(0, j + 1), at(0, j)});
        mesh.indices.insert(mesh.indices.end(), {end, at(rings - 1, j), at(rings - 1, j + 1)});
        for (int i = 0; i + 1 < rings; ++i)
            mesh.indices.insert(mesh.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1),
                                                     at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
}

Texture blankTexture(int w, int h) {
    Texture t;
    t.width = w;
    t.height = h;
    t.linear.assign(size_t(w) * h, RGB{1, 1, 1});
    return t;
}

// Square spirals ("greek key" meanders), 3 px lines, colour per 32 px tile.
Texture greekTexture() {
    Texture t = blankTexture(512, 512);
    const RGB palette[7] = {{0, 0.6f, 0.9f}, {0.85f, 0.05f, 0.45f}, {0.95f, 0.85f, 0.05f}, {0.02f, 0.02f, 0.02f},
                            {0.8f, 0.1f, 0.05f}, {0.05f, 0.5f, 0.1f}, {0.1f, 0.1f, 0.6f}};
    for (int ty = 0; ty < 16; ++ty)
        for (int tx = 0; tx < 16; ++tx) {
            const RGB& col = palette[(tx * 3 + ty * 5) % 7];
            int x = tx * 32 + 15, y = ty * 32 + 15;
            const int dx[4] = {1, 0, -1, 0}, dy[4] = {0, 1, 0, -1};
            for (int seg = 0, len = 4; seg < 10; ++seg, len += (seg % 2 == 0) ? 4 : 0) {
                for (int s = 0; s < len; ++s) {
                    for (int a = -1; a <= 1; ++a)
                        for (int b = -1; b <= 1; ++b) {
                            int px = x + a, py = y + b;
                            if (px >= tx * 32 + 1 && px < tx * 32 + 31 && py >= ty * 32 + 1 && py < ty * 32 + 31)
                                t.linear[size_t(py) * 512 + px] = col;
                        }
                    x += dx[seg % 4];
                    y += dy[seg % 4];
                }
            }
        }
    return t;
}

// Dark and orange spots on white.
Texture spotsTexture() {
    Texture t = blankTexture(512, 256);
    Rng rng(2021, 7);
    const RGB palette[3] = {{0.03f, 0.02f, 0.02f}, {0.7f, 0.25f, 0.02f}, {0.25f, 0.12f, 0.05f}};
    for (int k = 0; k < 140; ++k) {
        float cx = rng.uniform() * 512, cy = rng.uniform() * 256, r = 5 + 14 * rng.uniform();
        const RGB& col = palette[rng.next32() % 3];
        for (int y = int(cy - r); y <= int(cy + r); ++y)
            for (int x = int(cx - 2 * r); x <= int(cx + 2 * r); ++x) {
                float ex = (x - cx) / 2.0f, ey = y - cy;  // u spans 2x the v texels
                if (ex * ex + ey * ey > r * r) continue;
                t.linear[size_t((y % 256 + 256) % 256) * 512 + size_t((x % 512 + 512) % 512)] = col;
            }
    }
    return t;
}

// The clear block's labels (ResearchLabel) at the printer's voxel size,
// voxel centres inside [0, 10]^3 mm, two void voxels around.
LabelGrid clearBlock() {
    constexpr Label kVoid = kVoidLabel, kWhite = kWhiteLabel, kClear = kClearLabel;
    const Vec3f voxel_mm = kPrinterVoxel_mm;
    const float size_mm = 10.0f;
    GridFrame frame;
    for (int a = 0; a < 3; ++a) frame.resolution[a] = int(std::ceil(size_mm / voxel_mm[a])) + 4;
    frame.voxelSize_mm = voxel_mm;
    frame.cornerMin_mm = {-2 * voxel_mm.x, -2 * voxel_mm.y, -2 * voxel_mm.z};
    LabelGridBuilder builder(frame, kVoid);
    for (int z = 0; z < frame.resolution.z; ++z) {
        for (int y = 0; y < frame.resolution.y; ++y)
            for (int x = 0; x < frame.resolution.x; ++x) {
                const Point3f c = frame.voxelCenter_mm({x, y, z});
                if (c.x < 0 || c.y < 0 || c.z < 0 || c.x > size_mm || c.y > size_mm || c.z > size_mm) continue;
                Label label = kClear;
                const float half = 0.5f * size_mm;
                if (std::abs(c.x - half) < 2 && std::abs(c.y - half) < 2 && std::abs(c.z - half) < 2) label = kWhite;
                const float depth_mm = size_mm - c.z, ring_mm = std::hypot(c.x - half, c.y - half);
                if (depth_mm > 0.1f && depth_mm < 0.6f && ring_mm > 2.0f && ring_mm < 3.5f) {
                    // A halftone: of five voxels three magenta, one black, one white.
                    const uint64_t h = mix64(uint64_t(x) * 73856093u ^ uint64_t(y) * 19349663u ^ uint64_t(z) * 83492791u);
                    label = h % 5 < 3 ? Label(kMagentaLabel) : h % 5 == 3 ? Label(kBlackLabel) : kWhite;
                }
                builder.set({x, y, z}, label);
            }
        if (z % 32 == 0) builder.compact();
    }
    return builder.finish();
}

// The learned predictor's training volumes (scripts/train_learned.py):
// cuboids (60 %) and ellipsoids of printer voxels, 1.5-12 mm across (small
// ones likelier; thin plates of 0.6-1.5 mm, and ellipsoids as thin rods
// or discs, too), with
// a white, clear or mixed core under 1-3 layers. Each layer is a random
// mixture of the printer's resins, dithered voxel by voxel with white
// noise: one mixture, regions (cells 0.1-3 mm wide, turned at random) of
// mixtures from a palette, or stripes and dots of a second mixture.
struct Mixture {
    std::array<float, 7> share{};  // per research label; void (5) stays 0
    Label pick(float u) const {
        for (int l = 0; l < 7; ++l)
            if ((u -= share[size_t(l)]) < 0) return Label(l);
        return kWhiteLabel;
    }
};

Mixture randomMixture(Rng& rng) {
    Mixture m;
    const int inks = 1 + int(rng.next32() % 3);
    float total = 0;
    for (int k = 0; k < inks; ++k) {
        static const Label kInks[6] = {kCyanLabel, kMagentaLabel, kYellowLabel, kBlackLabel, kWhiteLabel, kClearLabel};
        const Label ink = kInks[rng.next32() % (rng.uniform() < 0.1f ? 6 : 5)];
        const float w = rng.uniform() + 0.05f;
        m.share[ink] += w;
        total += w;
    }
    for (float& s : m.share) s /= total;
    return m;
}

struct Layer {
    enum class Kind { Uniform, Regions, Pattern } kind;
    float bottom_mm;  // depth under the surface where the layer ends
    Mixture mixture, second;
    std::vector<Mixture> palette;  // regions: the cells' mixtures
    Vec3f stripe{0, 0, 1};          // regions: the cells' turned z axis; stripes: their normal
    float period_mm = 0, fill = 0;
    bool dots = false;
};

// One to three layers under the surface, each of one mixture, of regions
// of random mixtures or of a pattern (stripes or dots) of two.
std::vector<Layer> randomLayers(Rng& rng) {
    std::vector<Layer> layers(size_t(1 + rng.next32() % 3));
    float depth_mm = 0;
    for (Layer& layer : layers) {
        depth_mm += 0.05f + (rng.uniform() < 0.5f ? 0.3f : 1.2f) * rng.uniform();
        layer.bottom_mm = depth_mm;
        layer.mixture = randomMixture(rng);
        const float kind = rng.uniform();
        layer.kind = kind < 0.3f ? Layer::Kind::Uniform : kind < 0.65f ? Layer::Kind::Regions : Layer::Kind::Pattern;
        const float phi = 2 * kPi * rng.uniform(), cosTheta = 2 * rng.uniform() - 1;
        const float sinTheta = std::sqrt(std::max(0.0f, 1 - cosTheta * cosTheta));
        layer.stripe = {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
        if (layer.kind == Layer::Kind::Regions) {
            layer.period_mm = 0.1f + 2.9f * rng.uniform() * rng.uniform();
            for (int k = 0; k < 8; ++k) layer.palette.push_back(randomMixture(rng));
        } else if (layer.kind == Layer::Kind::Pattern) {
            layer.second = randomMixture(rng);
            layer.period_mm = 0.1f + 1.4f * rng.uniform() * rng.uniform();
            layer.fill = 0.1f + 0.5f * rng.uniform();
            layer.dots = rng.uniform() < 0.4f;
        }
    }
    return layers;
}

// The mixture at a voxel centre this deep: its layer's, or the core's.
const Mixture* mixtureAt(const Point3f& c, float depth, const std::vector<Layer>& layers, const Mixture& coreMixture) {
    const Mixture* mixture = &coreMixture;
    for (const Layer& layer : layers) {
        if (depth >= layer.bottom_mm) continue;
        mixture = &layer.mixture;
        if (layer.kind == Layer::Kind::Regions) {
            const Frame turned(layer.stripe);
            const Vec3f q = c * (1.0f / layer.period_mm);
            const uint64_t cell = mix64(uint64_t(int64_t(std::floor(dot(q, turned.s))) * 73856093) ^
                                        uint64_t(int64_t(std::floor(dot(q, turned.t))) * 19349663) ^
                                        uint64_t(int64_t(std::floor(dot(q, turned.n))) * 83492791));
            mixture = &layer.palette[cell % layer.palette.size()];
        } else if (layer.kind == Layer::Kind::Pattern) {
            float phase = dot(c, layer.stripe) / layer.period_mm;
            bool inside = phase - std::floor(phase) < layer.fill;
            if (layer.dots) {
                const Vec3f q = c * (1.0f / layer.period_mm);
                const Vec3f f{q.x - std::floor(q.x) - 0.5f, q.y - std::floor(q.y) - 0.5f, q.z - std::floor(q.z) - 0.5f};
                inside = std::sqrt(dot(f, f)) < 0.6f * layer.fill;
            }
            if (inside) mixture = &layer.second;
        }
        break;
    }
    return mixture;
}

void writeTrainingVolume(uint64_t seed, int index, const std::filesystem::path& dir) {
    Rng rng(seed, uint64_t(index));
    const Vec3f voxel_mm = kPrinterVoxel_mm;  // prepare's voxels
    Vec3f size_mm;
    for (int a = 0; a < 3; ++a) size_mm[a] = 1.5f + 10.5f * rng.uniform() * rng.uniform();
    if (rng.uniform() < 0.25f) size_mm[int(rng.next32() % 3)] = 0.6f + 0.9f * rng.uniform();  // a thin plate
    // The shape from its own stream: an ellipsoid inscribed in the box, as
    // a rod when two of its diameters are made small.
    Rng shapeRng(seed ^ 0x5eed5eedull, uint64_t(index));
    const bool ellipsoid = shapeRng.uniform() < 0.4f;
    if (ellipsoid && shapeRng.uniform() < 0.4f) {
        const int keep = int(shapeRng.next32() % 3);
        for (int a = 0; a < 3; ++a)
            if (a != keep) size_mm[a] = std::min(size_mm[a], 0.6f + 2.4f * shapeRng.uniform());
    }
    const Vec3f radius_mm = size_mm * 0.5f;
    auto inside = [&](const Point3f& c) {
        if (!ellipsoid) return c.x >= 0 && c.y >= 0 && c.z >= 0 && c.x <= size_mm.x && c.y <= size_mm.y && c.z <= size_mm.z;
        const Vec3f q{(c.x - radius_mm.x) / radius_mm.x, (c.y - radius_mm.y) / radius_mm.y, (c.z - radius_mm.z) / radius_mm.z};
        return dot(q, q) <= 1.0f;
    };
    // Depth under the surface: exact for the cuboid and a sphere, about
    // right for an ellipsoid.
    auto depthOf = [&](const Point3f& c) {
        if (!ellipsoid) return std::min({c.x, c.y, c.z, size_mm.x - c.x, size_mm.y - c.y, size_mm.z - c.z});
        const Vec3f q{(c.x - radius_mm.x) / radius_mm.x, (c.y - radius_mm.y) / radius_mm.y, (c.z - radius_mm.z) / radius_mm.z};
        return (1.0f - std::sqrt(dot(q, q))) * std::min({radius_mm.x, radius_mm.y, radius_mm.z});
    };
    const std::vector<Layer> layers = randomLayers(rng);
    const float core = rng.uniform();
    Mixture coreMixture = randomMixture(rng);
    if (core < 0.7f) coreMixture = Mixture{}, coreMixture.share[kWhiteLabel] = 1;
    else if (core < 0.8f) coreMixture = Mixture{}, coreMixture.share[kClearLabel] = 1;

    GridFrame frame;
    for (int a = 0; a < 3; ++a) frame.resolution[a] = int(std::ceil(size_mm[a] / voxel_mm[a])) + 4;
    frame.voxelSize_mm = voxel_mm;
    frame.cornerMin_mm = {-2 * voxel_mm.x, -2 * voxel_mm.y, -2 * voxel_mm.z};
    LabelGridBuilder builder(frame, kVoidLabel);
    for (int z = 0; z < frame.resolution.z; ++z) {
        for (int y = 0; y < frame.resolution.y; ++y)
            for (int x = 0; x < frame.resolution.x; ++x) {
                const Point3f c = frame.voxelCenter_mm({x, y, z});
                if (!inside(c)) continue;
                const float depth = depthOf(c);
                const uint64_t h = mix64(seed ^ (uint64_t(index) << 48) ^ uint64_t(x) * 73856093u ^
                                         uint64_t(y) * 19349663u ^ uint64_t(z) * 83492791u);
                const float u = float(h >> 40) / float(1 << 24);
                const Mixture* mixture = mixtureAt(c, depth, layers, coreMixture);
                builder.set({x, y, z}, mixture->pick(u));
            }
        if (z % 32 == 0) builder.compact();
    }
    char name[32];
    std::snprintf(name, sizeof(name), "train_%03d", index);
    writeLabelGridVdb(builder.finish(), dir / (std::string(name) + ".vdb"));
    TriangleMesh mesh;
    SurfaceAppearance look;
    if (ellipsoid) {
        ellipsoidMesh(radius_mm, mesh, look);
    } else {
        cube(1.0f, mesh, look);
        for (Point3f& p : mesh.positions_mm) p = {p.x * size_mm.x, p.y * size_mm.y, p.z * size_mm.z};
    }
    writeGltf(mesh, look, "", dir / (std::string(name) + ".gltf"));
}

}  // namespace

int main(int argc, char** argv) {
    // make-test-data --training N SEED OUTDIR: N training volumes.
    if (argc == 5 && std::string(argv[1]) == "--training") {
        try {
            const int count = std::stoi(argv[2]);
            const uint64_t seed = std::stoull(argv[3]);
            std::filesystem::create_directories(argv[4]);
            for (int i = 0; i < count; ++i) writeTrainingVolume(seed, i, argv[4]);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "make-test-data: error: %s\n", e.what());
            return 1;
        }
        std::printf("make-test-data: wrote %s training volumes to %s\n", argv[2], argv[4]);
        return 0;
    }
    if (argc != 2) {
        std::fprintf(stderr, "usage: make-test-data OUTDIR | make-test-data --training N SEED OUTDIR\n");
        return 2;
    }
    std::filesystem::path dir = argv[1];
    try {
        std::filesystem::create_directories(dir);
        writeTexturePng(greekTexture(), dir / "greek.png");
        writeTexturePng(spotsTexture(), dir / "spots.png");
        SurfaceAppearance textured;
        textured.materials.push_back({{1, 1, 1}, 0});

        for (float size : {10.0f, 20.0f}) {
            TriangleMesh mesh;
            SurfaceAppearance look = textured;
            cube(size, mesh, look);
            std::string name = "cube" + std::to_string(int(size));
            writeGltf(mesh, look, "greek.png", dir / (name + "_greek.gltf"));
            look.materials.clear();
            writeGltf(mesh, look, "", dir / (name + ".gltf"));
        }

        TriangleMesh animal;
        SurfaceAppearance animalLook = textured;
        sweep(240, 24,
              [](float s) { return Point3f(0.8f * std::sin(3 * kPi * s), 4.6f * std::sin(1.6f * kPi * s), 12.0f * s); },
              [](float s, float) { return 0.3f + 1.9f * std::pow(std::max(0.0f, std::sin(kPi * s)), 0.8f) * (1.0f - 0.6f * s); },
              animal, animalLook);
        writeGltf(animal, animalLook, "spots.png", dir / "animal_spotted.gltf");
        animalLook.materials.clear();
        writeGltf(animal, animalLook, "", dir / "animal.gltf");

        TriangleMesh bone;
        SurfaceAppearance boneLook;
        sweep(320, 96, [](float s) { return Point3f(30.0f * s, 0.0f, 0.0f); },
              [](float s, float phi) {
                  float knobs = 4.0f * (std::exp(-std::pow(s / 0.09f, 2.0f)) + std::exp(-std::pow((1 - s) / 0.09f, 2.0f)));
                  float ridges = 1.0f + 0.06f * std::sin(3 * phi) * std::sin(11 * kPi * s);
                  return (2.8f + knobs) * ridges;
              },
              bone, boneLook);
        writeGltf(bone, boneLook, "", dir / "bone.gltf");

        writeLabelGridVdb(clearBlock(), dir / "cube10_clear.vdb");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "make-test-data: error: %s\n", e.what());
        return 1;
    }
    std::printf("make-test-data: wrote the test-set models to %s\n", dir.string().c_str());
    return 0;
}
