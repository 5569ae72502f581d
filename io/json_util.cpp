#include "io/json_util.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/input_error.h"

namespace pl {

namespace {
std::string keyName(const std::string& where, const char* key) {
    return where.empty() ? std::string(key) : where + "." + key;
}
}  // namespace

JsonReader::JsonReader(const std::filesystem::path& file) : fileName_(file.string()) {
    std::ifstream in(file);
    if (!in) throw InputError(fileName_, "cannot open file");
    std::stringstream ss;
    ss << in.rdbuf();
    try {
        root_ = nlohmann::json::parse(ss.str());
    } catch (const nlohmann::json::exception& e) {  // parse_error; out_of_range for numbers such as 9e999
        std::string msg = e.what();
        // nlohmann's message is "[json.exception.parse_error.101] parse error at line ..."
        auto pos = msg.find("] ");
        throw InputError(fileName_, "malformed JSON: " +
                                        (pos == std::string::npos ? msg : msg.substr(pos + 2)));
    }
}

void JsonReader::fail(const std::string& key, const std::string& problem) const {
    throw InputError(fileName_, key.empty() ? problem : "'" + key + "' " + problem);
}

void JsonReader::expectOnlyKeys(const nlohmann::json& obj, const std::string& where,
                                std::initializer_list<const char*> allowed) const {
    expectOnlyKeys(obj, where, std::vector<std::string>(allowed.begin(), allowed.end()));
}

void JsonReader::expectOnlyKeys(const nlohmann::json& obj, const std::string& where,
                                const std::vector<std::string>& allowed) const {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
        bool ok = false;
        for (const std::string& a : allowed) ok = ok || it.key() == a;
        if (!ok) fail(keyName(where, it.key().c_str()), "is not a known key");
    }
}

const nlohmann::json& JsonReader::object(const nlohmann::json& parent, const char* key,
                                         const std::string& where) const {
    auto it = parent.find(key);
    if (it == parent.end()) fail(keyName(where, key), "is missing");
    if (!it->is_object()) fail(keyName(where, key), "must be an object");
    return *it;
}

double JsonReader::number(const nlohmann::json& obj, const char* key,
                          const std::string& where) const {
    auto it = obj.find(key);
    if (it == obj.end()) fail(keyName(where, key), "is missing");
    if (!it->is_number()) fail(keyName(where, key), "must be a number");
    double v = it->get<double>();
    if (!std::isfinite(v)) fail(keyName(where, key), "must be finite");
    return v;
}

double JsonReader::number(const nlohmann::json& obj, const char* key, const std::string& where,
                          double fallback) const {
    return obj.contains(key) ? number(obj, key, where) : fallback;
}

int64_t JsonReader::integer(const nlohmann::json& obj, const char* key,
                            const std::string& where) const {
    auto it = obj.find(key);
    if (it == obj.end()) fail(keyName(where, key), "is missing");
    if (!it->is_number_integer()) fail(keyName(where, key), "must be an integer");
    return it->get<int64_t>();
}

int64_t JsonReader::integer(const nlohmann::json& obj, const char* key, const std::string& where,
                            int64_t fallback) const {
    return obj.contains(key) ? integer(obj, key, where) : fallback;
}

bool JsonReader::boolean(const nlohmann::json& obj, const char* key, const std::string& where,
                         bool fallback) const {
    auto it = obj.find(key);
    if (it == obj.end()) return fallback;
    if (!it->is_boolean()) fail(keyName(where, key), "must be true or false");
    return it->get<bool>();
}

std::string JsonReader::string(const nlohmann::json& obj, const char* key,
                               const std::string& where) const {
    auto it = obj.find(key);
    if (it == obj.end()) fail(keyName(where, key), "is missing");
    if (!it->is_string()) fail(keyName(where, key), "must be a string");
    return it->get<std::string>();
}

std::string JsonReader::string(const nlohmann::json& obj, const char* key,
                               const std::string& where, const std::string& fallback) const {
    return obj.contains(key) ? string(obj, key, where) : fallback;
}

RGB JsonReader::rgb(const nlohmann::json& obj, const char* key, const std::string& where) const {
    auto it = obj.find(key);
    if (it == obj.end()) fail(keyName(where, key), "is missing");
    if (it->is_number()) {
        float v = float(number(obj, key, where));
        return {v, v, v};
    }
    if (!it->is_array() || it->size() != 3)
        fail(keyName(where, key), "must be a number or a list of three numbers");
    RGB out;
    for (int c = 0; c < 3; ++c) {
        const auto& e = (*it)[size_t(c)];
        if (!e.is_number()) fail(keyName(where, key), "must hold numbers");
        double v = e.get<double>();
        if (!std::isfinite(v)) fail(keyName(where, key), "must be finite");
        out[c] = float(v);
    }
    return out;
}

Vec3f JsonReader::vec3(const nlohmann::json& obj, const char* key, const std::string& where) const {
    auto it = obj.find(key);
    if (it == obj.end()) fail(keyName(where, key), "is missing");
    if (!it->is_array() || it->size() != 3) fail(keyName(where, key), "must be a list of three numbers");
    RGB v = rgb(obj, key, where);
    return {v[0], v[1], v[2]};
}

}  // namespace pl
