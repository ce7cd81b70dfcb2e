// Random wavy strands for the geometry tests (header only: the test globs take *.cpp).
#pragma once

#include "scene/scene.h"

#include <cmath>
#include <cstdint>
#include <random>

namespace httest {

// `ns` strands of `nseg` segments starting inside [-1,1]^3 scaled by `scale`, segment length
// ~seg_len, direction bent by up to `bend` per segment; radius r, or with radius_jitter j each
// point's radius uniform in r (1 +- j).  A given seed gives the same strands whatever j is not
// used for (the jitter draws only when j != 0).
inline ht::Strands random_strands(uint32_t seed, int ns, int nseg, double seg_len, double r, double bend = 0.3,
                                  double scale = 1.0, double radius_jitter = 0.0) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    ht::Strands s;
    s.first_point.push_back(0);
    for (int i = 0; i < ns; ++i) {
        double p[3] = {u(rng) * scale, u(rng) * scale, u(rng) * scale};
        double d[3] = {u(rng), u(rng), u(rng)};
        for (int j = 0; j <= nseg; ++j) {
            s.points.push_back({(float)p[0], (float)p[1], (float)p[2]});
            s.radius.push_back((float)(radius_jitter != 0.0 ? r * (1 + radius_jitter * u(rng)) : r));
            const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            for (int k = 0; k < 3; ++k) p[k] += d[k] / n * seg_len;
            for (int k = 0; k < 3; ++k) d[k] = d[k] / n + bend * u(rng);
        }
        s.first_point.push_back((uint32_t)s.points.size());
        s.material.push_back(0);
    }
    return s;
}

}  // namespace httest
