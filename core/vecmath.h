// Small vector types. Point3f/Vec3f are millimetres (world space);
// Vec3i is a voxel coordinate (index space). Keep the two apart.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace pl {

struct Vec3f {
    float x = 0, y = 0, z = 0;
    Vec3f() = default;
    constexpr Vec3f(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
    float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    Vec3f operator+(const Vec3f& b) const { return {x + b.x, y + b.y, z + b.z}; }
    Vec3f operator-(const Vec3f& b) const { return {x - b.x, y - b.y, z - b.z}; }
    Vec3f operator-() const { return {-x, -y, -z}; }
    Vec3f operator*(float s) const { return {x * s, y * s, z * s}; }
    Vec3f operator/(float s) const { return {x / s, y / s, z / s}; }
    Vec3f& operator+=(const Vec3f& b) { x += b.x; y += b.y; z += b.z; return *this; }
};
using Point3f = Vec3f;

inline Vec3f operator*(float s, const Vec3f& v) { return v * s; }
inline float dot(const Vec3f& a, const Vec3f& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3f cross(const Vec3f& a, const Vec3f& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(const Vec3f& v) { return std::sqrt(dot(v, v)); }
inline Vec3f normalize(const Vec3f& v) { return v / length(v); }
inline Vec3f vmin(const Vec3f& a, const Vec3f& b) {
    return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
inline Vec3f vmax(const Vec3f& a, const Vec3f& b) {
    return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}

struct Vec3i {
    int32_t x = 0, y = 0, z = 0;
    Vec3i() = default;
    constexpr Vec3i(int32_t x_, int32_t y_, int32_t z_) : x(x_), y(y_), z(z_) {}
    int32_t operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    int32_t& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    Vec3i operator+(const Vec3i& b) const { return {x + b.x, y + b.y, z + b.z}; }
    Vec3i operator-(const Vec3i& b) const { return {x - b.x, y - b.y, z - b.z}; }
    bool operator==(const Vec3i& b) const { return x == b.x && y == b.y && z == b.z; }
    bool operator!=(const Vec3i& b) const { return !(*this == b); }
    bool operator<(const Vec3i& b) const {
        return x != b.x ? x < b.x : (y != b.y ? y < b.y : z < b.z);
    }
};

// Orthonormal basis around a unit vector (Duff et al. 2017).
struct Frame {
    Vec3f s, t, n;
    explicit Frame(const Vec3f& n_) : n(n_) {
        float sign = std::copysign(1.0f, n.z);
        float a = -1.0f / (sign + n.z);
        float b = n.x * n.y * a;
        s = {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
        t = {b, sign + n.y * n.y * a, -n.y};
    }
    Vec3f toWorld(const Vec3f& v) const { return s * v.x + t * v.y + n * v.z; }
};

struct Ray {
    Point3f o;
    Vec3f d;  // unit length
    // Surfaces nearer than this are ignored (a ray spawned on a surface
    // must not hit it again); media are not: they start at o.
    float tMin = 0.0f;
    // A ray spawned into the object starts surfaceLift inside the surface;
    // the medium it still has to cross before o, along -d (its flights count
    // it: flightFromSurface in integrators/integrator.h).
    float mediumBefore_mm = 0.0f;
    Point3f at(float t) const { return o + d * t; }
};

constexpr float kPi = 3.14159265358979323846f;

}  // namespace pl
