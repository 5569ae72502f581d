// Image outputs through OpenImageIO: EXR (linear RGB, coverage alpha and
// per-channel standard error) and PNG previews (sRGB, 8 bit).
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/film.h"
#include "core/sensors.h"
#include "prepare/surface_appearance.h"

namespace pl {

struct RadianceImage {
    int width = 0, height = 0;
    std::vector<RGB> mean, standardError;
    std::vector<float> coverage;  // 1 where a sensor pixel lands, else 0
    // Written as "printlight:<key>" string attributes of the EXR header
    // (scene, seed, spp, ...), so a result says how it was made.
    std::vector<std::pair<std::string, std::string>> metadata;
};

// Lays the film out in the sensor's image (the atlas for surface voxels).
RadianceImage filmToImage(const Film& film, const Sensor& sensor);

// EXR channels: R, G, B, A (coverage), stderr.R, stderr.G, stderr.B.
void writeExr(const RadianceImage& image, const std::filesystem::path& file);
void writePng(const RadianceImage& image, const std::filesystem::path& file);

// Reads an EXR written by writeExr (for tests and comparisons).
RadianceImage readExr(const std::filesystem::path& file);

// Texture images: 8/16-bit files are sRGB-encoded, float files (EXR) linear.
Texture readTexture(const std::filesystem::path& file);
// Writes an 8-bit sRGB PNG.
void writeTexturePng(const Texture& texture, const std::filesystem::path& file);

}  // namespace pl
