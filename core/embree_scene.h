// An Embree device and scene, created together and released together (the
// mesh's triangles, printlight's prism index).
#pragma once

#include <embree3/rtcore.h>

#include <stdexcept>

namespace pl {

struct EmbreeScene {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    EmbreeScene() {
        device = rtcNewDevice(nullptr);
        if (!device) throw std::runtime_error("cannot create an Embree device");
        scene = rtcNewScene(device);
    }
    ~EmbreeScene() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;
};

}  // namespace pl
