// Writes an output through a temporary file beside it, renamed into place
// on commit(); dropped without commit (error, exception) it removes the
// temporary, so no partial file ever stands under the output name.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace pl {

class OutputFile {
public:
    explicit OutputFile(std::filesystem::path finalPath);
    ~OutputFile();
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;

    const std::filesystem::path& tempPath() const { return temp_; }
    const std::filesystem::path& finalPath() const { return final_; }
    void commit();

private:
    std::filesystem::path final_, temp_;
    bool committed_ = false;
};

// Writes `text` to `file` through an OutputFile (never a partial file).
void writeTextFile(const std::filesystem::path& file, const std::string& text);

// Throws InputError if `output` names the same file as any of `inputs`.
void refuseToOverwriteInputs(const std::filesystem::path& output,
                             const std::vector<std::filesystem::path>& inputs);

}  // namespace pl
