// Reading JSON input files with errors that name the file and the key.
#pragma once

#include <array>
#include <filesystem>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/enum_names.h"
#include "core/rgb.h"
#include "core/vecmath.h"

namespace pl {

class JsonReader {
public:
    // Parses the file; throws InputError on a missing file or bad JSON.
    explicit JsonReader(const std::filesystem::path& file);

    const nlohmann::json& root() const { return root_; }
    const std::string& fileName() const { return fileName_; }

    [[noreturn]] void fail(const std::string& key, const std::string& problem) const;
    // Rejects keys outside `allowed` (catches typos such as "desnity").
    void expectOnlyKeys(const nlohmann::json& obj, const std::string& where,
                        std::initializer_list<const char*> allowed) const;
    void expectOnlyKeys(const nlohmann::json& obj, const std::string& where,
                        const std::vector<std::string>& allowed) const;

    const nlohmann::json& object(const nlohmann::json& parent, const char* key,
                                 const std::string& where) const;
    double number(const nlohmann::json& obj, const char* key, const std::string& where) const;
    double number(const nlohmann::json& obj, const char* key, const std::string& where,
                  double fallback) const;
    int64_t integer(const nlohmann::json& obj, const char* key, const std::string& where) const;
    int64_t integer(const nlohmann::json& obj, const char* key, const std::string& where,
                    int64_t fallback) const;
    bool boolean(const nlohmann::json& obj, const char* key, const std::string& where,
                 bool fallback) const;
    std::string string(const nlohmann::json& obj, const char* key, const std::string& where) const;
    std::string string(const nlohmann::json& obj, const char* key, const std::string& where,
                       const std::string& fallback) const;
    // One of an enum's names (core/enum_names.h), or the fallback's where
    // the key is absent.
    template <class Enum, size_t N>
    Enum choice(const nlohmann::json& obj, const char* key, const std::string& where,
                const std::array<EnumName<Enum>, N>& names, Enum fallback) const {
        const std::optional<Enum> value = parseEnum(names, string(obj, key, where, enumName(names, fallback)));
        if (!value) fail(where + "." + key, "must be " + enumNames(names));
        return *value;
    }
    // A number broadcast to all three, or a list of three numbers.
    RGB rgb(const nlohmann::json& obj, const char* key, const std::string& where) const;
    Vec3f vec3(const nlohmann::json& obj, const char* key, const std::string& where) const;

private:
    std::string fileName_;
    nlohmann::json root_;
};

}  // namespace pl
