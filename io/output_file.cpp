#include "io/output_file.h"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <system_error>

#include "core/input_error.h"

namespace pl {

OutputFile::OutputFile(std::filesystem::path finalPath) : final_(std::move(finalPath)) {
    static std::atomic<int> counter{0};
    // Keep the extension last: OpenImageIO picks the format from it.
    temp_ = final_.parent_path() /
            (final_.stem().string() + ".tmp" + std::to_string(getpid()) + "-" +
             std::to_string(counter++) + final_.extension().string());
    if (!final_.parent_path().empty()) {
        std::error_code ec;
        std::filesystem::create_directories(final_.parent_path(), ec);
        if (ec) throw InputError(final_.string(), "cannot create output folder: " + ec.message());
    }
}

OutputFile::~OutputFile() {
    if (!committed_) {
        std::error_code ec;
        std::filesystem::remove(temp_, ec);
    }
}

void OutputFile::commit() {
    std::error_code ec;
    std::filesystem::rename(temp_, final_, ec);
    if (ec) throw InputError(final_.string(), "cannot write output: " + ec.message());
    committed_ = true;
}

void writeTextFile(const std::filesystem::path& file, const std::string& text) {
    OutputFile out(file);
    {
        std::ofstream os(out.tempPath());
        os << text;
        if (!os) throw InputError(file.string(), "write failed");
    }
    out.commit();
}

void refuseToOverwriteInputs(const std::filesystem::path& output,
                             const std::vector<std::filesystem::path>& inputs) {
    std::error_code ec;
    if (!std::filesystem::exists(output, ec)) return;
    for (const auto& in : inputs)
        if (std::filesystem::equivalent(output, in, ec))
            throw InputError(output.string(), "output would overwrite an input file");
}

}  // namespace pl
