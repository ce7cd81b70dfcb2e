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
    // render --aovs: HT_AOV_OUT sums per pixel (kernels/aovs.h), empty without; films add them
    // like rgba, and host/render/aovs.h turns them into named channels.
    std::vector<float> aov;
    // render --target-error: the (r, g, b, n) sums of the pixel's even-numbered samples only, 4
    // floats per pixel, empty without; films add them like rgba, and the difference between this
    // half and the rest is the error estimate of render/adaptive.h.
    std::vector<float> even;
    // mean radiance of pixel i, channel c
    float mean(size_t i, int c) const {
        float n = rgba[4 * i + 3];
        return n > 0 ? rgba[4 * i + c] / n : 0.0f;
    }
};

}  // namespace ht
