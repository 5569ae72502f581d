// PCG32 random numbers (O'Neill 2014) with counter-based seeding, so that the
// stream of a (seed, pixel, sample, channel) tuple does not depend on which
// thread renders it or in what order.
#pragma once

#include <cstdint>

namespace pl {

// SplitMix64 finaliser: a bijective 64-bit mixer.
inline uint64_t mix64(uint64_t z) {
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

class Rng {
public:
    Rng(uint64_t state, uint64_t stream) { seed(state, stream); }

    // One independent stream per path: key the state and the stream increment.
    static Rng forPath(uint64_t seed, uint64_t pixel, uint64_t sample, uint64_t channel) {
        uint64_t a = mix64(seed ^ mix64(pixel));
        uint64_t b = mix64(a ^ mix64(sample * 4 + channel + 0x632be59bd9b4e019ull));
        return Rng(b, a);
    }

    void seed(uint64_t state, uint64_t stream) {
        state_ = 0;
        inc_ = (stream << 1u) | 1u;
        next32();
        state_ += state;
        next32();
    }

    uint32_t next32() {
        uint64_t old = state_;
        state_ = old * 6364136223846793005ull + inc_;
        uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
        uint32_t rot = uint32_t(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
    }

    // Uniform in [0, 1), never 1.
    float uniform() { return float(next32() >> 8) * 0x1p-24f; }

private:
    uint64_t state_ = 0, inc_ = 0;
};

}  // namespace pl
