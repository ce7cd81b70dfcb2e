// Image error against a reference: the numbers behind every "run time against error" claim.
#pragma once

#include <cstddef>
#include <vector>

namespace ht {

// A pixel is a sparkle when, in some channel, its error exceeds kSparkleFactor times the
// reference's local noise there (issue 14's "sparkles, counted"; definition at local_noise()).
constexpr double kSparkleFactor = 10.0;

struct ErrorMetrics {
    double rmse = 0;      // sqrt(mean over pixels and channels of (x - ref)^2)
    double relmse = 0;    // mean of (x - ref)^2 / (ref^2 + 1e-2), robust to dark pixels (Rousselle et al.)
    double max_abs = 0;   // largest |x - ref|
    double mean = 0, ref_mean = 0;
    double channel_mean[3] = {0, 0, 0}, ref_channel_mean[3] = {0, 0, 0};  // the same, per rgb channel
    size_t nonfinite = 0; // NaN/Inf values in the image (counted, excluded from the rest)
    size_t sparkles = 0;  // pixels with max_c |x_c - ref_c| / local_noise_c > kSparkleFactor
    double sparkle_share = 0;  // sparkles / pixels (a pixel with a non-finite value counts as one)
};

// rgb and ref hold 3 floats per pixel of a width x height image, row by row.
ErrorMetrics compare_images(const std::vector<float>& rgb, const std::vector<float>& ref, int width, int height);

// The reference's local noise, per pixel and channel (3 floats per pixel): the standard deviation
// of the reference's channel over the 3x3 pixels centred on the pixel (fewer at the border;
// non-finite values left out), but at least kNoiseFloor times the reference's mean over the whole
// image and all channels (so that exact zeros around a pixel -- background -- do not make
// a float rounding a sparkle). Over flat regions this is the reference's own noise; where the
// image has detail at pixel scale (fibre edges) it is larger than the noise, so the count is
// conservative there: a sparkle must stand out from everything the reference shows around it.
constexpr double kNoiseFloor = 1e-2;
std::vector<float> local_noise(const std::vector<float>& ref, int width, int height);

}  // namespace ht
