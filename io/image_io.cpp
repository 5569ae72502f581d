#include "io/image_io.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>

#include "core/input_error.h"
#include "io/output_file.h"

namespace pl {

namespace {
float linearToSrgb(float v) {
    v = std::clamp(v, 0.0f, 1.0f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

void writeImage(const std::filesystem::path& file, const OIIO::ImageSpec& spec, const void* data) {
    OutputFile out(file);
    auto img = OIIO::ImageOutput::create(out.tempPath().string());
    if (!img) throw InputError(file.string(), "cannot create image writer: " + OIIO::geterror());
    if (!img->open(out.tempPath().string(), spec) || !img->write_image(spec.format, data) ||
        !img->close())
        throw InputError(file.string(), "cannot write image: " + img->geterror());
    img.reset();
    out.commit();
}
}  // namespace

RadianceImage filmToImage(const Film& film, const Sensor& sensor) {
    RadianceImage im;
    im.width = sensor.imageWidth();
    im.height = sensor.imageHeight();
    size_t n = size_t(im.width) * im.height;
    im.mean.assign(n, RGB{0, 0, 0});
    im.standardError.assign(n, RGB{0, 0, 0});
    im.coverage.assign(n, 0.0f);
    for (size_t p = 0; p < film.pixelCount(); ++p) {
        int64_t i = sensor.pixelImageIndex(p);
        if (i < 0) continue;
        im.mean[size_t(i)] = film.meanRGB(p);
        im.standardError[size_t(i)] = film.standardErrorRGB(p);
        im.coverage[size_t(i)] = 1.0f;
    }
    return im;
}

RadianceImage filmToPixelImage(const Film& film, int width) {
    RadianceImage im;
    size_t n = film.pixelCount();
    im.width = int(std::max<size_t>(1, std::min<size_t>(n, size_t(width))));
    im.height = int(std::max<size_t>(1, (n + size_t(im.width) - 1) / size_t(im.width)));
    size_t slots = size_t(im.width) * im.height;
    im.mean.assign(slots, RGB{0, 0, 0});
    im.standardError.assign(slots, RGB{0, 0, 0});
    im.coverage.assign(slots, 0.0f);
    for (size_t p = 0; p < n; ++p) {
        im.mean[p] = film.meanRGB(p);
        im.standardError[p] = film.standardErrorRGB(p);
        im.coverage[p] = 1.0f;
    }
    return im;
}

PixelResults pixelResultsOf(const RadianceImage& image, size_t pixelCount) {
    PixelResults r;
    pixelCount = std::min(pixelCount, image.mean.size());
    r.mean.assign(image.mean.begin(), image.mean.begin() + pixelCount);
    r.standardError.assign(image.standardError.begin(), image.standardError.begin() + pixelCount);
    return r;
}

void writeExr(const RadianceImage& image, const std::filesystem::path& file) {
    OIIO::ImageSpec spec(image.width, image.height, 7, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "A", "stderr.R", "stderr.G", "stderr.B"};
    spec.alpha_channel = 3;
    spec.attribute("compression", "zip");
    for (const auto& [key, value] : image.metadata) spec.attribute("printlight:" + key, value);
    std::vector<float> data(size_t(image.width) * image.height * 7);
    for (size_t i = 0; i < image.mean.size(); ++i) {
        float* px = &data[i * 7];
        for (int c = 0; c < 3; ++c) {
            px[c] = image.mean[i][c];
            px[4 + c] = image.standardError[i][c];
        }
        px[3] = image.coverage[i];
    }
    writeImage(file, spec, data.data());
}

void writePng(const RadianceImage& image, const std::filesystem::path& file) {
    OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
    std::vector<uint8_t> data(size_t(image.width) * image.height * 3);
    for (size_t i = 0; i < image.mean.size(); ++i)
        for (int c = 0; c < 3; ++c)
            data[i * 3 + c] = uint8_t(std::lround(255.0f * linearToSrgb(image.mean[i][c])));
    writeImage(file, spec, data.data());
}

RadianceImage readExr(const std::filesystem::path& file) {
    auto in = OIIO::ImageInput::open(file.string());
    if (!in) throw InputError(file.string(), "cannot read image: " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.nchannels != 7) throw InputError(file.string(), "not a printlight EXR (7 channels)");
    RadianceImage im;
    im.width = spec.width;
    im.height = spec.height;
    std::vector<float> data(size_t(im.width) * im.height * 7);
    if (!in->read_image(0, 0, 0, 7, OIIO::TypeDesc::FLOAT, data.data()))
        throw InputError(file.string(), "cannot read image: " + in->geterror());
    size_t n = size_t(im.width) * im.height;
    im.mean.resize(n);
    im.standardError.resize(n);
    im.coverage.resize(n);
    // EXR stores channels sorted by name: look each one up.
    int ch[7];
    const char* names[7] = {"R", "G", "B", "A", "stderr.R", "stderr.G", "stderr.B"};
    for (int k = 0; k < 7; ++k) {
        ch[k] = spec.channelindex(names[k]);
        if (ch[k] < 0) throw InputError(file.string(), std::string("missing channel ") + names[k]);
    }
    for (size_t i = 0; i < n; ++i) {
        const float* px = &data[i * 7];
        im.mean[i] = {px[ch[0]], px[ch[1]], px[ch[2]]};
        im.coverage[i] = px[ch[3]];
        im.standardError[i] = {px[ch[4]], px[ch[5]], px[ch[6]]};
    }
    for (const OIIO::ParamValue& attr : spec.extra_attribs) {
        std::string name = attr.name().string();
        if (name.rfind("printlight:", 0) == 0 && attr.type() == OIIO::TypeDesc::STRING)
            im.metadata.emplace_back(name.substr(11), attr.get_string());
    }
    return im;
}

Texture readTexture(const std::filesystem::path& file) {
    auto in = OIIO::ImageInput::open(file.string());
    if (!in) {
        std::string msg = OIIO::geterror();
        for (char& c : msg) if (c == '\n') c = ' ';
        throw InputError(file.string(), "cannot read texture: " + msg);
    }
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels < 1 || int64_t(spec.width) * spec.height > (int64_t(1) << 28))
        throw InputError(file.string(), "texture has an unusable size");
    std::vector<float> data(size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data.data()))
        throw InputError(file.string(), "cannot read texture: " + in->geterror());
    bool encoded = spec.format.basetype == OIIO::TypeDesc::UINT8 || spec.format.basetype == OIIO::TypeDesc::UINT16;
    return Texture::fromInterleaved(spec.width, spec.height, spec.nchannels, data, encoded);
}

namespace {
std::vector<uint8_t> srgb8(const Texture& texture) {
    std::vector<uint8_t> data(texture.linear.size() * 3);
    for (size_t i = 0; i < texture.linear.size(); ++i)
        for (int c = 0; c < 3; ++c)
            data[i * 3 + c] = uint8_t(std::lround(255.0f * linearToSrgb(texture.linear[i][c])));
    return data;
}
}  // namespace

void writeTexturePng(const Texture& texture, const std::filesystem::path& file) {
    OIIO::ImageSpec spec(texture.width, texture.height, 3, OIIO::TypeDesc::UINT8);
    writeImage(file, spec, srgb8(texture).data());
}

std::vector<unsigned char> texturePngBytes(const Texture& texture) {
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    OIIO::ImageSpec spec(texture.width, texture.height, 3, OIIO::TypeDesc::UINT8);
    auto img = OIIO::ImageOutput::create("texture.png");
    if (!img || !img->set_ioproxy(&proxy) || !img->open("texture.png", spec) ||
        !img->write_image(spec.format, srgb8(texture).data()) || !img->close())
        throw std::runtime_error("cannot encode a PNG: " + (img ? img->geterror() : OIIO::geterror()));
    return bytes;
}

}  // namespace pl
