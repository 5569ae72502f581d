#include "api/printer_characterisation.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/input_error.h"
#include "io/materials_io.h"
#include "io/printer_gamut_io.h"
#include "runtime/progress.h"
#include "render/registry.h"
#include "render/render.h"

namespace pl {

namespace {

constexpr int kFormatVersion = 1;

// FNV-1a over the bytes of the values the colours depend on.
struct KeyHash {
    uint64_t h = 1469598103934665603ULL;
    void bytes(const void* p, size_t n) {
        const auto* b = static_cast<const unsigned char*>(p);
        for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ULL;
    }
    template <typename T>
    void value(const T& v) { bytes(&v, sizeof v); }
};

std::string settingsJson(const CharacterisationSettings& s) {
    char text[512];
    std::snprintf(text, sizeof text,
                  "{\"levels\": %d, \"voxel_mm\": [%g, %g, %g], \"shell_depth_mm\": %g, \"cube_mm\": %g, "
                  "\"measured_square_mm\": %g, \"integrator\": \"%s\", \"spp\": %u, \"seed\": %llu, \"ior\": %g}",
                  s.levels, s.voxel_mm.x, s.voxel_mm.y, s.voxel_mm.z, s.shellDepth_mm, s.cube_mm,
                  s.measuredSquare_mm, s.integrator.c_str(), s.spp, (unsigned long long)s.seed, s.ior);
    return text;
}

}  // namespace

std::string characterisationKey(const MaterialTable& materials, const CharacterisationSettings& settings) {
    KeyHash k;
    k.value(kFormatVersion);
    for (int label = 0; label < 256; ++label) {
        const Material& m = materials.byLabel[size_t(label)];
        if (!m.defined) continue;
        k.value(label);
        k.value(m.sigmaT_perMm);
        k.value(m.albedo);
        k.value(m.g);
    }
    const std::string s = settingsJson(settings);
    k.bytes(s.data(), s.size());
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", (unsigned long long)k.h);
    return hex;
}

PrinterGamut characterisePrinter(const MaterialTable& materials, const CharacterisationSettings& settings,
                                 bool showProgress) {
    for (Label l : kPrintMaterialLabel)
        if (!materials.byLabel[l].defined)
            throw std::invalid_argument(std::string("characterising the printer needs a material for label ") +
                                        std::to_string(int(l)) + " (" + researchLabelName(l) + ")");
    const Vec3f& h = settings.voxel_mm;
    GridFrame frame;
    frame.voxelSize_mm = h;
    frame.resolution = {std::max(4, int(std::lround(settings.cube_mm / h.x))),
                        std::max(4, int(std::lround(settings.cube_mm / h.y))),
                        std::max(4, int(std::lround(settings.cube_mm / h.z)))};
    const Vec3i& res = frame.resolution;
    // The shell as optimize finds it on a flat face: voxels whose centre is
    // within the depth of a surface voxel's centre.
    std::vector<uint8_t> inShell(frame.voxelCount());
    for (int z = 0, i = 0; z < res.z; ++z)
        for (int y = 0; y < res.y; ++y)
            for (int x = 0; x < res.x; ++x, ++i) {
                const float depth_mm = std::min({std::min(x, res.x - 1 - x) * h.x, std::min(y, res.y - 1 - y) * h.y,
                                                 std::min(z, res.z - 1 - z) * h.z});
                inShell[size_t(i)] = depth_mm <= settings.shellDepth_mm;
            }
    auto labelsOf = [&](const MaterialFractions& mixture) {
        std::vector<Label> labels(frame.voxelCount(), kWhiteLabel);
        halftoneFrame(
            res,
            [&](size_t i, MaterialFractions& f) {
                f = mixture;
                return inShell[i] != 0;
            },
            [&](size_t i, int material) { labels[i] = kPrintMaterialLabel[material]; });
        return LabelGrid::fromDense(frame, labels, kVoidLabel);
    };

    RenderSettings rs;
    setIntegrator(rs, settings.integrator);
    rs.spp = settings.spp;
    rs.seed = settings.seed;
    const SceneNeeds needs = sceneNeedsOf(rs);
    if (needs.surfaceFields)
        throw std::invalid_argument("the printer is characterised with an estimator that needs no surface fields");
    Scene scene;
    scene.geometry = std::make_unique<Geometry>(
        boxMesh({0, 0, 0}, {res.x * h.x, res.y * h.y, res.z * h.z}));
    scene.ior = settings.ior;
    scene.environment = {1, 1, 1};
    if (needs.clearance) scene.clearance = std::make_unique<SurfaceClearance>(*scene.geometry, frame);

    const std::vector<MaterialFractions> mixtures = PrinterGamut::gridMixtures(settings.levels);
    std::vector<RGB> reflectance(mixtures.size()), standardError(mixtures.size());
    ProgressBar bar(mixtures.size(), "characterising the printer", showProgress && ProgressBar::stderrIsTerminal());
    std::unique_ptr<SurfaceVoxelSensor> sensor;
    PixelShare measured;
    for (size_t k = 0; k < mixtures.size(); ++k) {
        scene.medium = std::make_unique<LabelMedium>(labelsOf(mixtures[k]), materials);
        if (!sensor) {
            // The same surface voxels for every mixture: the box is full.
            sensor = std::make_unique<SurfaceVoxelSensor>(*scene.geometry, frame, scene.medium->grid().surfaceVoxels(),
                                                          SurfaceVoxelSensor::Footprint::Patch);
            const float centre[3] = {0.5f * res.x * h.x, 0.5f * res.y * h.y, 0.5f * res.z * h.z};
            const float half = 0.5f * settings.measuredSquare_mm;
            for (size_t p = 0; p < sensor->pixelCount(); ++p) {
                const auto& px = sensor->pixels()[p];
                const float n[3] = {std::abs(px.normal.x), std::abs(px.normal.y), std::abs(px.normal.z)};
                const int axis = n[0] > 0.9f ? 0 : n[1] > 0.9f ? 1 : n[2] > 0.9f ? 2 : -1;
                if (axis < 0) continue;
                const float q[3] = {px.surfacePoint_mm.x, px.surfacePoint_mm.y, px.surfacePoint_mm.z};
                bool inside = true;
                for (int a = 0; a < 3; ++a)
                    if (a != axis && std::abs(q[a] - centre[a]) > half) inside = false;
                if (inside) measured.pixels.push_back(uint32_t(p));
            }
            if (measured.pixels.empty()) throw std::invalid_argument("characterisation: no face centre to measure");
        }
        const std::unique_ptr<Integrator> integrator = makeIntegrator(scene, *sensor, rs);
        RenderResult r{Film(sensor->pixelCount())};
        renderSamples(*integrator, scene, *sensor, rs, measured, 0, rs.spp, r);
        gatherShares(r, measured, *sensor);
        double sum[3] = {0, 0, 0}, var[3] = {0, 0, 0};
        for (uint32_t p : measured.pixels) {
            const RGB m = r.film.meanRGB(p), e = r.film.standardErrorRGB(p);
            for (int c = 0; c < 3; ++c) sum[c] += m[size_t(c)], var[c] += double(e[size_t(c)]) * e[size_t(c)];
        }
        const double n = double(measured.pixels.size());
        for (int c = 0; c < 3; ++c) {
            reflectance[k][size_t(c)] = float(sum[c] / n);
            standardError[k][size_t(c)] = float(std::sqrt(var[c]) / n);
        }
        bar.advance(1);
    }
    bar.finish();
    return PrinterGamut(settings.levels, std::move(reflectance), std::move(standardError));
}

void writeCharacterisation(const PrinterGamut& gamut, const MaterialTable& materials,
                           const CharacterisationSettings& settings, const std::filesystem::path& file) {
    writePrinterGamut(gamut, characterisationKey(materials, settings), settingsJson(settings), file);
}

PrinterGamut printerGamutFor(const std::filesystem::path& materialsFile, const CharacterisationSettings& settings,
                             const std::function<void(const std::string&)>& said) {
    const MaterialTable materials = loadMaterials(materialsFile);
    const std::string key = characterisationKey(materials, settings);
    const std::filesystem::path beside =
        materialsFile.parent_path() / (materialsFile.stem().string() + ".gamut.json");
    if (auto g = readPrinterGamut(beside, key)) {
        if (said) said("the printer's gamut: " + beside.string());
        return std::move(*g);
    }
    std::filesystem::path cacheDir;
    if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) cacheDir = x;
    else if (const char* home = std::getenv("HOME"); home && *home) cacheDir = std::filesystem::path(home) / ".cache";
    const std::filesystem::path cached =
        cacheDir.empty() ? std::filesystem::path() : cacheDir / "printlight" / (key + ".gamut.json");
    if (!cached.empty())
        if (auto g = readPrinterGamut(cached, key)) {
            if (said) said("the printer's gamut: " + cached.string());
            return std::move(*g);
        }
    PrinterGamut gamut = characterisePrinter(materials, settings, true);
    std::string where = "not kept (no cache folder)";
    if (!cached.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(cached.parent_path(), ec);
        try {
            writeCharacterisation(gamut, materials, settings, cached);
            where = "kept in " + cached.string();
        } catch (const std::exception& e) {
            where = std::string("not kept: ") + e.what();
        }
    }
    if (said) said("the printer's gamut: characterised " + std::to_string(gamut.gridReflectance().size()) + " mixtures of " +
                   materialsFile.string() + ", " + where);
    return gamut;
}

PrinterGamut readPrinterGamutFile(const std::filesystem::path& file, const std::filesystem::path& materialsFile,
                                  const CharacterisationSettings& settings,
                                  const std::function<void(const std::string&)>& said) {
    if (!std::filesystem::exists(file)) throw InputError(file.string(), "no such file");
    std::string found;
    std::optional<PrinterGamut> g = readPrinterGamut(file, "", &found);
    if (said) {
        const bool matches = found == characterisationKey(loadMaterials(materialsFile), settings);
        said("the printer's gamut: " + file.string() +
             (matches ? "" : " (made for other materials or settings than this scene's)"));
    }
    return std::move(*g);
}

}  // namespace pl
