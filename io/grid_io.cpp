#include "io/grid_io.h"

#include <zlib.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include <openvdb/io/File.h>

#include "io/file_names.h"
#include "runtime/memory_budget.h"
#include "core/input_error.h"
#include "io/output_file.h"
#include "media/label_tree.h"
#include "media/materials.h"
#include "media/voxel_fields_vdb.h"

namespace pl {

namespace {

constexpr Label kDefaultVoidLabel = kVoidLabel;  // "air" in the research label convention

// Memory per voxel of the frame, for refusing jobs that cannot fit: a dense
// read holds the labels (1 byte) and builds the tree (up to ~1.2 bytes when
// nothing is uniform); a .vdb is sparse already, and what rendering adds per
// voxel (majorant bricks, surface clearance: 4 bytes per 4^3 block) is small.
constexpr double kDenseReadBytesPerVoxel = 2.3, kSparseBytesPerVoxel = 0.25;

// Validates a resolution read from a file header; bytesPerVoxel: what the
// dense read and the label tree take per voxel.
void checkResolution(const std::string& name, const int32_t res[3], double bytesPerVoxel) {
    uint64_t n = 1;
    for (int a = 0; a < 3; ++a) {
        if (res[a] <= 0 || res[a] > (1 << 24))
            throw InputError(name, "absurd resolution " + std::to_string(res[0]) + "x" +
                                       std::to_string(res[1]) + "x" + std::to_string(res[2]));
        n *= uint64_t(res[a]);
    }
    if (n > kMaxGridVoxels) throw InputError(name, "grid of " + std::to_string(n) + " voxels is too large");
    if (auto why = memoryShortfall(uint64_t(double(n) * bytesPerVoxel), "reading " + std::to_string(n) + " voxels"))
        throw InputError(name, *why);
}

GridFrame frameFromBox(const std::string& name, const int32_t res[3], const double lo[3],
                       const double hi[3]) {
    GridFrame f;
    for (int a = 0; a < 3; ++a) {
        if (!std::isfinite(lo[a]) || !std::isfinite(hi[a]) || !(hi[a] > lo[a]))
            throw InputError(name, "invalid bounding box");
        f.resolution[a] = res[a];
        f.cornerMin_mm[a] = float(lo[a]);
        f.voxelSize_mm[a] = float((hi[a] - lo[a]) / res[a]);
    }
    return f;
}

// Byte source over a plain or gzip file.
class ByteReader {
public:
    ByteReader(const std::filesystem::path& file, bool gzip) : name_(file.string()) {
        if (gzip) {
            gz_ = gzopen(name_.c_str(), "rb");
            if (!gz_) throw InputError(name_, "cannot open file");
        } else {
            in_.open(file, std::ios::binary);
            if (!in_) throw InputError(name_, "cannot open file");
        }
    }
    ~ByteReader() {
        if (gz_) gzclose(gz_);
    }
    void read(void* dst, size_t n, const char* what) {
        if (gz_) {
            auto* p = static_cast<char*>(dst);
            while (n > 0) {
                unsigned chunk = unsigned(std::min<size_t>(n, 1u << 30));
                int got = gzread(gz_, p, chunk);
                if (got <= 0) throw InputError(name_, std::string("truncated or corrupt file (") + what + ")");
                p += got;
                n -= size_t(got);
            }
        } else {
            in_.read(static_cast<char*>(dst), std::streamsize(n));
            if (size_t(in_.gcount()) != n) throw InputError(name_, std::string("truncated file (") + what + ")");
        }
    }
    // Throws before a big allocation if a plain file cannot hold n more
    // bytes (a corrupt header must not make us allocate what is not there).
    // A gzip stream's length is unknown: readInChunks grows as data arrive.
    void expectAtLeast(uint64_t n, const char* what) {
        if (gz_) return;
        auto here = in_.tellg();
        in_.seekg(0, std::ios::end);
        auto end = in_.tellg();
        in_.seekg(here);
        if (here < 0 || end < 0 || uint64_t(end - here) < n)
            throw InputError(name_, std::string("truncated file (") + what + ": header promises " + std::to_string(n) +
                                        " bytes, " + std::to_string(end >= here ? uint64_t(end - here) : 0) + " remain)");
    }
    template <class T>
    std::vector<T> readArray(size_t count, const char* what) {
        expectAtLeast(uint64_t(count) * sizeof(T), what);
        std::vector<T> out;
        const size_t chunk = (size_t(64) << 20) / sizeof(T);
        while (out.size() < count) {
            size_t at = out.size(), n = std::min(chunk, count - at);
            out.resize(at + n);
            read(out.data() + at, n * sizeof(T), what);
        }
        return out;
    }
    bool atEnd() {
        char c;
        if (gz_) return gzread(gz_, &c, 1) == 0;
        in_.read(&c, 1);
        return in_.gcount() == 0;
    }

private:
    std::string name_;
    std::ifstream in_;
    gzFile gz_ = nullptr;
};

LabelGrid loadLabelGridBin(const std::filesystem::path& file, bool gzip, Label voidLabel) {
    const std::string name = file.string();
    ByteReader in(file, gzip);
    int32_t res[3];
    double lo[3], hi[3];
    in.read(res, sizeof res, "header");
    in.read(lo, sizeof lo, "header");
    in.read(hi, sizeof hi, "header");
    checkResolution(name, res, kDenseReadBytesPerVoxel);
    GridFrame frame = frameFromBox(name, res, lo, hi);
    std::vector<Label> labels = in.readArray<Label>(frame.voxelCount(), "labels");
    if (!in.atEnd()) throw InputError(name, "trailing data after the labels (wrong resolution?)");
    return LabelGrid::fromDense(frame, labels, voidLabel);
}

LabelGrid loadLabelGridVol(const std::filesystem::path& file, Label voidLabel) {
    const std::string name = file.string();
    ByteReader in(file, false);
    char magic[4];
    in.read(magic, 4, "header");
    if (std::memcmp(magic, "VOL", 3) != 0 || magic[3] != 3) throw InputError(name, "not a Mitsuba VOL v3 file");
    int32_t encoding, res[3], channels;
    float box[6];
    in.read(&encoding, 4, "header");
    in.read(res, sizeof res, "header");
    in.read(&channels, 4, "header");
    in.read(box, sizeof box, "header");
    checkResolution(name, res, kDenseReadBytesPerVoxel + 4);  // float32 data are read whole
    if (channels != 1) throw InputError(name, "a label grid needs 1 channel, found " + std::to_string(channels));
    double lo[3] = {box[0], box[1], box[2]}, hi[3] = {box[3], box[4], box[5]};
    GridFrame frame = frameFromBox(name, res, lo, hi);
    std::vector<Label> labels;
    if (encoding == 3) {
        labels = in.readArray<Label>(frame.voxelCount(), "data");
    } else if (encoding == 1) {
        std::vector<float> values = in.readArray<float>(frame.voxelCount(), "data");
        labels.resize(values.size());
        for (size_t i = 0; i < values.size(); ++i) {
            float v = values[i];
            if (!(v >= 0 && v <= 255 && v == std::floor(v)))
                throw InputError(name, "voxel value " + std::to_string(v) + " is not a label in 0..255");
            labels[i] = Label(v);
        }
    } else {
        throw InputError(name, "unsupported VOL encoding " + std::to_string(encoding) +
                                   " (labels need 1 = float32 or 3 = uint8)");
    }
    if (!in.atEnd()) throw InputError(name, "trailing data after the voxels (wrong resolution?)");
    return LabelGrid::fromDense(frame, labels, voidLabel);
}

// Converts integer-valued grids of other value types to 8-bit labels.
template <class GridT>
LabelTreeType::Ptr toLabelTree(const GridT& grid, const std::string& name) {
    using V = typename GridT::ValueType;
    auto toLabel = [&](V v) {
        double d = double(v);
        if (!(d >= 0 && d <= 255 && d == std::floor(d)))
            throw InputError(name, "grid 'labels' holds " + std::to_string(d) + ", not a label in 0..255");
        return Label(d);
    };
    auto out = std::make_shared<LabelTreeType>(toLabel(grid.background()));
    for (auto it = grid.tree().cbeginValueAll(); it; ++it) {
        if (*it == grid.background()) continue;
        openvdb::CoordBBox box;
        it.getBoundingBox(box);
        out->fill(box, toLabel(*it), true);
    }
    return out;
}

LabelGrid loadLabelGridVdb(const std::filesystem::path& file, std::optional<Label> voidOverride) {
    const std::string name = file.string();
    initializeVdb();
    openvdb::GridBase::Ptr base;
    try {
        openvdb::io::File f(name);
        f.open(false);
        if (!f.hasGrid("labels")) {
            f.close();
            throw InputError(name, "no grid named 'labels'");
        }
        base = f.readGrid("labels");
        f.close();
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        std::string msg = e.what();
        for (char& c : msg) if (c == '\n') c = ' ';
        throw InputError(name, "cannot read VDB: " + msg);
    }
    auto tree = std::make_shared<LabelGrid::Tree>();
    if (auto g = openvdb::GridBase::grid<LabelVdbGrid>(base)) tree->vdb = g->treePtr();
    else if (auto gi = openvdb::GridBase::grid<openvdb::Int32Grid>(base)) tree->vdb = toLabelTree(*gi, name);
    else if (auto gf = openvdb::GridBase::grid<openvdb::FloatGrid>(base)) tree->vdb = toLabelTree(*gf, name);
    else throw InputError(name, "grid 'labels' has unsupported type " + base->type());

    // The transform must be a per-axis scale and translation.
    const openvdb::math::Transform& xf = base->transform();
    openvdb::Mat4d m = xf.baseMap()->getAffineMap()->getMat4();
    if (!xf.isLinear() || m(0, 1) != 0 || m(0, 2) != 0 || m(1, 0) != 0 || m(1, 2) != 0 ||
        m(2, 0) != 0 || m(2, 1) != 0)
        throw InputError(name, "grid 'labels' must have an axis-aligned scale+translate transform");
    openvdb::Vec3d vs = xf.voxelSize();

    // The frame: stored by printlight, else the bounding box of non-void values.
    GridFrame frame;
    openvdb::CoordBBox box;
    auto minMeta = base->getMetadata<openvdb::Vec3IMetadata>("printlight_index_min");
    auto resMeta = base->getMetadata<openvdb::Vec3IMetadata>("printlight_resolution");
    if (minMeta && resMeta) {
        openvdb::Vec3i lo = minMeta->value(), r = resMeta->value();
        box = openvdb::CoordBBox(openvdb::Coord(lo), openvdb::Coord(lo + r - openvdb::Vec3i(1)));
    } else {
        tree->vdb->evalLeafBoundingBox(box);
    }
    if (box.empty()) throw InputError(name, "grid 'labels' is empty");
    int32_t res[3] = {box.dim().x(), box.dim().y(), box.dim().z()};
    checkResolution(name, res, kSparseBytesPerVoxel);
    for (int a = 0; a < 3; ++a) {
        if (!(vs[a] > 0) || !std::isfinite(vs[a])) throw InputError(name, "invalid voxel size");
        frame.indexMin[a] = box.min()[a];
        frame.resolution[a] = res[a];
        frame.voxelSize_mm[a] = float(vs[a]);
    }
    // OpenVDB puts voxel centres at integer index coordinates.
    openvdb::Vec3d c = xf.indexToWorld(openvdb::Vec3d(box.min().x(), box.min().y(), box.min().z()));
    frame.cornerMin_mm = {float(c.x() - 0.5 * vs.x()), float(c.y() - 0.5 * vs.y()), float(c.z() - 0.5 * vs.z())};

    Label background = tree->vdb->background();
    if (voidOverride && *voidOverride != background)
        throw InputError(name, "void label " + std::to_string(*voidOverride) +
                                   " differs from the grid's background " + std::to_string(background));
    return LabelGrid(frame, background, std::move(tree));
}

openvdb::math::Transform::Ptr transformOf(const GridFrame& f) {
    openvdb::Vec3d vs(f.voxelSize_mm.x, f.voxelSize_mm.y, f.voxelSize_mm.z);
    auto xf = openvdb::math::Transform::createLinearTransform(openvdb::Mat4d::identity());
    xf->preScale(vs);
    // Voxel centre of index i is cornerMin + (i - indexMin + 0.5) * size.
    openvdb::Vec3d t;
    for (int a = 0; a < 3; ++a)
        t[a] = double(f.cornerMin_mm[a]) + (0.5 - f.indexMin[a]) * vs[a];
    xf->postTranslate(t);
    return xf;
}

void writeVdbGrids(const openvdb::GridPtrVec& grids, const std::filesystem::path& file) {
    OutputFile out(file);
    openvdb::io::File f(out.tempPath().string());
    f.write(grids);
    f.close();
    out.commit();
}

}  // namespace

std::shared_ptr<const VoxelFields> loadVoxelFields(const std::filesystem::path& file, const GridFrame& labels) {
    if (lowerExtension(file) != ".vdb") return nullptr;
    initializeVdb();
    const std::string name = file.string();
    openvdb::FloatGrid::Ptr sdf;
    openvdb::Vec3SGrid::Ptr normal;
    try {
        openvdb::io::File f(name);
        f.open(false);
        if (f.hasGrid("sdf") && f.hasGrid("normal")) {
            sdf = openvdb::GridBase::grid<openvdb::FloatGrid>(f.readGrid("sdf"));
            normal = openvdb::GridBase::grid<openvdb::Vec3SGrid>(f.readGrid("normal"));
        }
        f.close();
    } catch (const std::exception& e) {
        std::string msg = e.what();
        for (char& c : msg) if (c == '\n') c = ' ';
        throw InputError(name, "cannot read VDB: " + msg);
    }
    if (!sdf || !normal) return nullptr;
    for (const auto& g : {openvdb::GridBase::ConstPtr(sdf), openvdb::GridBase::ConstPtr(normal)}) {
        openvdb::Vec3d vs = g->transform().voxelSize();
        for (int a = 0; a < 3; ++a)
            if (std::abs(vs[a] - labels.voxelSize_mm[a]) > 1e-6 * labels.voxelSize_mm[a])
                throw InputError(name, "grid '" + g->getName() + "' does not share the voxels of 'labels'");
    }
    auto grids = std::unique_ptr<VoxelFields::Grids>(
        new VoxelFields::Grids{sdf, normal, nullptr, sdf->getAccessor(), normal->getAccessor(), nullptr});
    return std::make_shared<const VoxelFields>(std::move(grids));
}

LabelGrid loadLabelGrid(const std::filesystem::path& file, std::optional<Label> voidLabel) {
    const std::string name = file.string();
    if (!std::filesystem::exists(file)) throw InputError(name, "cannot open file");
    std::string ext = lowerExtension(file);
    // A plain branch, not value_or: GCC turns that into a conditional move
    // reading the unset payload of an empty optional, and valgrind then
    // reports every voxel comparison with the void label as uninitialised.
    Label v = kDefaultVoidLabel;
    if (voidLabel.has_value()) {
        v = *voidLabel;
        asm volatile("" ::: "memory");  // keeps the branch a branch
    }
    if (ext == ".vdb") return loadLabelGridVdb(file, voidLabel);
    if (ext == ".bin") return loadLabelGridBin(file, false, v);
    if (ext == ".gz") return loadLabelGridBin(file, true, v);
    if (ext == ".vol") return loadLabelGridVol(file, v);
    throw InputError(name, "unknown label grid format (expected .vdb, .bin, .gz or .vol)");
}

namespace {
LabelVdbGrid::Ptr labelsVdbGrid(const LabelGrid& grid) {
    initializeVdb();
    auto g = LabelVdbGrid::create(grid.tree().vdb);
    g->setName("labels");
    g->setTransform(transformOf(grid.frame()));
    g->setGridClass(openvdb::GRID_UNKNOWN);
    const GridFrame& f = grid.frame();
    g->insertMeta("printlight_index_min", openvdb::Vec3IMetadata(openvdb::Vec3i(f.indexMin.x, f.indexMin.y, f.indexMin.z)));
    g->insertMeta("printlight_resolution",
                  openvdb::Vec3IMetadata(openvdb::Vec3i(f.resolution.x, f.resolution.y, f.resolution.z)));
    return g;
}
}  // namespace

void writeLabelGridVdb(const LabelGrid& grid, const std::filesystem::path& file) {
    writeVdbGrids({labelsVdbGrid(grid)}, file);
}

void writePreparedVdb(const LabelGrid& grid, const VoxelFields& fields, const std::filesystem::path& file) {
    auto labels = labelsVdbGrid(grid);
    const VoxelFields::Grids& g = fields.grids();
    openvdb::GridPtrVec grids{labels};
    auto add = [&](openvdb::GridBase::Ptr field, const char* name) {
        field->setName(name);
        field->setTransform(labels->transform().copy());
        field->insertMeta("units", openvdb::StringMetadata(std::string(name) == "sdf" ? "mm" : ""));
        grids.push_back(field);
    };
    if (g.sdf->activeVoxelCount() > 0) {  // none with prepare --band-mm 0
        add(g.sdf, "sdf");
        add(g.normal, "normal");
    }
    if (g.colors) add(g.colors, "colors");
    writeVdbGrids(grids, file);
}

void writeLabelGridBin(const LabelGrid& grid, const std::filesystem::path& file) {
    const GridFrame& f = grid.frame();
    int32_t res[3] = {f.resolution.x, f.resolution.y, f.resolution.z};
    Point3f hi = f.cornerMax_mm();
    double lo[3] = {f.cornerMin_mm.x, f.cornerMin_mm.y, f.cornerMin_mm.z};
    double hiD[3] = {hi.x, hi.y, hi.z};
    std::vector<Label> labels = grid.toDense();
    OutputFile out(file);
    bool gzip = lowerExtension(file) == ".gz";
    if (gzip) {
        gzFile gz = gzopen(out.tempPath().string().c_str(), "wb6");
        if (!gz) throw InputError(file.string(), "cannot write output");
        bool ok = gzwrite(gz, res, sizeof res) > 0 && gzwrite(gz, lo, sizeof lo) > 0 &&
                  gzwrite(gz, hiD, sizeof hiD) > 0;
        for (size_t off = 0; ok && off < labels.size(); off += (1u << 30))
            ok = gzwrite(gz, labels.data() + off, unsigned(std::min<size_t>(labels.size() - off, 1u << 30))) > 0;
        if (gzclose(gz) != Z_OK || !ok) throw InputError(file.string(), "write failed");
    } else {
        std::ofstream os(out.tempPath(), std::ios::binary);
        os.write(reinterpret_cast<const char*>(res), sizeof res);
        os.write(reinterpret_cast<const char*>(lo), sizeof lo);
        os.write(reinterpret_cast<const char*>(hiD), sizeof hiD);
        os.write(reinterpret_cast<const char*>(labels.data()), std::streamsize(labels.size()));
        if (!os) throw InputError(file.string(), "write failed");
    }
    out.commit();
}

void writeLabelGridVol(const LabelGrid& grid, const std::filesystem::path& file) {
    const GridFrame& f = grid.frame();
    Point3f hi = f.cornerMax_mm();
    int32_t header[5] = {3, f.resolution.x, f.resolution.y, f.resolution.z, 1};
    float box[6] = {f.cornerMin_mm.x, f.cornerMin_mm.y, f.cornerMin_mm.z, hi.x, hi.y, hi.z};
    std::vector<Label> labels = grid.toDense();
    OutputFile out(file);
    {
        std::ofstream os(out.tempPath(), std::ios::binary);
        os.write("VOL\x03", 4);
        os.write(reinterpret_cast<const char*>(header), sizeof header);
        os.write(reinterpret_cast<const char*>(box), sizeof box);
        os.write(reinterpret_cast<const char*>(labels.data()), std::streamsize(labels.size()));
        if (!os) throw InputError(file.string(), "write failed");
    }
    out.commit();
}

void writeSurfaceResultVdb(const GridFrame& frame, const std::vector<Vec3i>& voxels,
                           const PixelResults& results, const std::filesystem::path& file) {
    initializeVdb();
    auto radiance = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    auto stderrGrid = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    auto xf = transformOf(frame);
    radiance->setTransform(xf);
    stderrGrid->setTransform(xf->copy());
    radiance->setName("radiance");
    stderrGrid->setName("stderr");
    auto ra = radiance->getAccessor();
    auto sa = stderrGrid->getAccessor();
    for (size_t i = 0; i < voxels.size(); ++i) {
        const RGB& m = results.mean[i];
        const RGB& s = results.standardError[i];
        ra.setValueOn(toCoord(voxels[i]), openvdb::Vec3s(m[0], m[1], m[2]));
        sa.setValueOn(toCoord(voxels[i]), openvdb::Vec3s(s[0], s[1], s[2]));
    }
    writeVdbGrids({radiance, stderrGrid}, file);
}

}  // namespace pl
