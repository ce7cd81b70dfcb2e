// Deterministic random numbers for the scene generators: PCG32 (O'Neill 2014, XSH-RR output)
// seeded through SplitMix64.  Each hair draws from its own stream (seed, hair index), so a hair's
// shape depends only on its index: generation order and hair count do not change other hairs.
// Only integer arithmetic and one exact int->double conversion: identical on every platform
// (std::*_distribution is implementation-defined and is not used).
#pragma once

#include <cstdint>

namespace ht {

inline uint64_t splitmix64(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

class Pcg32 {
public:
    Pcg32(uint64_t seed, uint64_t stream)
        : state_(0), increment_((splitmix64(stream + 0x632BE59BD9B4E019ull) << 1) | 1u) {
        next();
        state_ += splitmix64(seed);
        next();
    }

    uint32_t next() {
        const uint64_t old = state_;
        state_ = old * 6364136223846793005ull + increment_;
        const uint32_t shifted = static_cast<uint32_t>(((old >> 18) ^ old) >> 27);
        const uint32_t rotation = static_cast<uint32_t>(old >> 59);
        return (shifted >> rotation) | (shifted << ((32 - rotation) & 31));
    }

    // Uniform in [0, 1).
    double uniform() { return next() * (1.0 / 4294967296.0); }
    // Uniform in [a, b).
    double uniform(double a, double b) { return a + (b - a) * uniform(); }

private:
    uint64_t state_;
    uint64_t increment_;
};

}  // namespace ht
