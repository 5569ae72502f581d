// Image outputs through OpenImageIO: EXR (linear RGB, coverage alpha and
// per-channel standard error) and PNG previews (sRGB, 8 bit).
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/film.h"
#include "compare/result_comparison.h"
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

    // The metadata value of `key`, or "" if it has none.
    std::string meta(const std::string& key) const {
        for (const auto& [k, v] : metadata)
            if (k == key) return v;
        return "";
    }
};

// Lays the film out in the sensor's image (the atlas for surface voxels).
RadianceImage filmToImage(const Film& film, const Sensor& sensor);

// The film in sensor-pixel order, `width` pixels per row (pixel i at
// column i % width, row i / width; coverage 0 past the last pixel). Batch
// results use it: every pixel, also voxels an atlas would hide.
RadianceImage filmToPixelImage(const Film& film, int width = 1024);
// Its inverse: the first `pixelCount` pixels of such an image.
PixelResults pixelResultsOf(const RadianceImage& image, size_t pixelCount);

// EXR channels: R, G, B, A (coverage), stderr.R, stderr.G, stderr.B.
void writeExr(const RadianceImage& image, const std::filesystem::path& file);
void writePng(const RadianceImage& image, const std::filesystem::path& file);

// Reads an EXR written by writeExr, metadata included (tests, comparisons).
RadianceImage readExr(const std::filesystem::path& file);

// Texture images: 8/16-bit files are sRGB-encoded, float files (EXR) linear.
Texture readTexture(const std::filesystem::path& file);
// Writes an 8-bit sRGB PNG.
void writeTexturePng(const Texture& texture, const std::filesystem::path& file);
// The same PNG in memory (a texture inside a .glb).
std::vector<unsigned char> texturePngBytes(const Texture& texture);

}  // namespace pl
