// The linear radiance film every render, checkpoint, partial image and output works on.
#pragma once

#include <cstddef>
#include <vector>

namespace ht {

// Per pixel (sum r, sum g, sum b, sample count): raw sums, so that films of different samples
// can be added (split/accumulation.h) and divided only when an image is written.
struct Film {
    int width = 0, height = 0;
    std::vector<float> rgba;  // 4 floats per pixel
    // mean radiance of pixel i, channel c
    float mean(size_t i, int c) const {
        float n = rgba[4 * i + 3];
        return n > 0 ? rgba[4 * i + c] / n : 0.0f;
    }
};

}  // namespace ht
