// The pixels near a pixel in the sensor's image: error pooling's window
// (Film), and the neighbours that other MPI ranks hold (runtime/distributed).
#pragma once

#include <cstdint>
#include <vector>

#include "core/sensors.h"

namespace pl {

class ImageNeighbourhood {
public:
    // Without a sensor every pixel is alone.
    ImageNeighbourhood(const Sensor* sensor, size_t pixelCount) : sensor_(sensor) {
        if (!sensor) return;
        width_ = sensor->imageWidth();
        height_ = sensor->imageHeight();
        pixelAt_.assign(size_t(width_) * size_t(height_), -1);
        for (size_t p = 0; p < pixelCount; ++p)
            if (const int64_t i = sensor->pixelImageIndex(p); i >= 0) pixelAt_[size_t(i)] = int32_t(p);
    }
    // Calls visit(q) for every pixel q within `radius` image pixels of p
    // along each axis, row by row (p among them), or for p alone where it
    // has no place in the image.
    template <class Visit>
    void forEachNear(size_t p, int radius, Visit&& visit) const {
        const int64_t imageIndex = sensor_ ? sensor_->pixelImageIndex(p) : -1;
        if (imageIndex < 0) return visit(p);
        const int x = int(imageIndex % width_), y = int(imageIndex / width_);
        for (int dy = -radius; dy <= radius; ++dy)
            for (int dx = -radius; dx <= radius; ++dx) {
                const int qx = x + dx, qy = y + dy;
                if (qx < 0 || qy < 0 || qx >= width_ || qy >= height_) continue;
                const int32_t q = pixelAt_[size_t(qy) * size_t(width_) + size_t(qx)];
                if (q >= 0) visit(size_t(q));
            }
    }

private:
    const Sensor* sensor_;
    int width_ = 0, height_ = 0;
    std::vector<int32_t> pixelAt_;  // pixel by image position, -1 where none
};

}  // namespace pl
