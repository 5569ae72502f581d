#include "render/batch_manifest.h"

#include <set>

#include "render/registry.h"
#include "io/json_util.h"
#include "render/scene_io.h"

namespace pl {

namespace {
bool isSafeName(const std::string& s) {
    if (s.empty() || s.size() > 128 || s[0] == '.') return false;
    for (char c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')) return false;
    return true;
}
}  // namespace

BatchManifest parseBatchManifest(const std::filesystem::path& file) {
    JsonReader json(file);
    const nlohmann::json& root = json.root();
    if (!root.is_object()) json.fail("", "must be a JSON object");
    json.expectOnlyKeys(root, "", {"renders", "comment"});
    if (!root.contains("renders") || !root["renders"].is_array() || root["renders"].empty())
        json.fail("renders", "must be a non-empty list of renders");
    BatchManifest m;
    m.file = file;
    std::set<std::string> names;
    const auto& renders = root["renders"];
    for (size_t i = 0; i < renders.size(); ++i) {
        const nlohmann::json& r = renders[i];
        std::string where = "renders[" + std::to_string(i) + "]";
        if (!r.is_object()) json.fail(where, "must be an object");
        json.expectOnlyKeys(r, where, {"name", "scene", "spp", "seed", "integrator", "channel", "comment"});
        BatchJob job;
        job.name = json.string(r, "name", where);
        if (!isSafeName(job.name))
            json.fail(where + ".name", "must be letters, digits, '_', '-' or '.' (a file name stem)");
        if (!names.insert(job.name).second) json.fail(where + ".name", "'" + job.name + "' is used twice");
        job.sceneFile = file.parent_path() / json.string(r, "scene", where);
        int64_t spp = json.integer(r, "spp", where);
        if (spp < 1 || spp > (int64_t(1) << 24)) json.fail(where + ".spp", "must be in 1..16777216");
        job.spp = uint32_t(spp);
        int64_t seed = json.integer(r, "seed", where);
        if (seed < 0) json.fail(where + ".seed", "must be >= 0");
        job.seed = uint64_t(seed);
        if (r.contains("integrator")) {
            std::string in = json.string(r, "integrator", where);
            if (!findIntegratorKind(in)) json.fail(where + ".integrator", "must be " + integratorNames());
            job.integrator = in;
        }
        if (r.contains("channel")) {
            auto ch = parseChannels(json.string(r, "channel", where));
            if (!ch) json.fail(where + ".channel", "must be r, g, b or rgb");
            job.channels = *ch;
        }
        m.jobs.push_back(std::move(job));
    }
    return m;
}

}  // namespace pl
