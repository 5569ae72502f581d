#include "io/label_changes_io.h"

#include <cstring>
#include <fstream>
#include <string>

#include "core/input_error.h"
#include "io/output_file.h"

namespace pl {

namespace {
constexpr char kMagic[] = "printlight-label-changes 1\n";

template <class T>
void put(std::ofstream& out, const T& v) {
    out.write(reinterpret_cast<const char*>(&v), sizeof v);
}
template <class T>
bool get(std::ifstream& in, T& v) {
    return bool(in.read(reinterpret_cast<char*>(&v), sizeof v));
}
}  // namespace

void writeLabelChanges(const std::filesystem::path& file, const LabelChangeHistory& history) {
    OutputFile output(file);
    {
        std::ofstream out(output.tempPath(), std::ios::binary);
        out.write(kMagic, sizeof kMagic - 1);
        put(out, uint32_t(history.size()));
        for (const auto& changes : history) {
            put(out, uint64_t(changes.size()));
            for (const LabelGrid::Change& c : changes) {
                put(out, int32_t(c.voxel.x));
                put(out, int32_t(c.voxel.y));
                put(out, int32_t(c.voxel.z));
                put(out, uint8_t(c.label));
            }
        }
        if (!out) throw std::runtime_error(file.string() + ": cannot write");
    }
    output.commit();
}

LabelChangeHistory readLabelChanges(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(file.string(), "cannot open file");
    char magic[sizeof kMagic - 1];
    uint32_t iterations = 0;
    if (!in.read(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof magic) != 0 || !get(in, iterations))
        throw InputError(file.string(), "not a file of label changes (optimize --record-changes)");
    LabelChangeHistory history(iterations);
    for (auto& changes : history) {
        uint64_t count = 0;
        if (!get(in, count) || count > (uint64_t(1) << 36))
            throw InputError(file.string(), "truncated or corrupt label changes");
        changes.resize(size_t(count));
        for (LabelGrid::Change& c : changes) {
            int32_t x = 0, y = 0, z = 0;
            uint8_t label = 0;
            if (!get(in, x) || !get(in, y) || !get(in, z) || !get(in, label))
                throw InputError(file.string(), "truncated or corrupt label changes");
            c = {{x, y, z}, Label(label)};
        }
    }
    return history;
}

}  // namespace pl
