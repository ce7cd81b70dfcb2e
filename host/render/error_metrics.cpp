#include "render/error_metrics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ht {

namespace {

double finite_mean(const std::vector<float>& v) {
    double sum = 0;
    size_t n = 0;
    for (float x : v)
        if (std::isfinite(x)) { sum += x; ++n; }
    return n ? sum / double(n) : 0.0;
}

}  // namespace

std::vector<float> local_noise(const std::vector<float>& ref, int width, int height) {
    if (width < 1 || height < 1 || ref.size() != 3 * size_t(width) * size_t(height))
        throw std::invalid_argument("reference size does not match width x height");
    const double floor = kNoiseFloor * std::fabs(finite_mean(ref));
    std::vector<float> noise(ref.size());
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c) {
                double sum = 0, sum2 = 0;
                int n = 0;
                for (int yy = std::max(0, y - 1); yy <= std::min(height - 1, y + 1); ++yy)
                    for (int xx = std::max(0, x - 1); xx <= std::min(width - 1, x + 1); ++xx) {
                        double v = ref[3 * (size_t(yy) * width + xx) + c];
                        if (!std::isfinite(v)) continue;
                        sum += v;
                        sum2 += v * v;
                        ++n;
                    }
                double var = n ? std::max(0.0, sum2 / n - (sum / n) * (sum / n)) : 0.0;
                noise[3 * (size_t(y) * width + x) + c] = float(std::max(std::sqrt(var), floor));
            }
    return noise;
}

ErrorMetrics compare_images(const std::vector<float>& rgb, const std::vector<float>& ref, int width, int height) {
    if (rgb.size() != ref.size()) throw std::invalid_argument("image and reference differ in size");
    const std::vector<float> noise = local_noise(ref, width, height);
    ErrorMetrics m;
    double se = 0, rel = 0, sum[3] = {0, 0, 0}, rsum[3] = {0, 0, 0};
    size_t n[3] = {0, 0, 0};
    for (size_t p = 0; p < rgb.size() / 3; ++p) {
        bool sparkle = false;
        for (size_t i = 3 * p; i < 3 * p + 3; ++i) {
            double x = rgb[i], r = ref[i];
            if (!std::isfinite(x)) { ++m.nonfinite; sparkle = true; continue; }
            if (!std::isfinite(r)) continue;
            double d = x - r;
            se += d * d;
            rel += d * d / (r * r + 1e-2);
            m.max_abs = std::max(m.max_abs, std::fabs(d));
            // noise[i] == 0 only when the whole reference is 0: then any error is a sparkle
            if (std::fabs(d) > kSparkleFactor * noise[i] && d != 0) sparkle = true;
            sum[i - 3 * p] += x;
            rsum[i - 3 * p] += r;
            ++n[i - 3 * p];
        }
        m.sparkles += sparkle;
    }
    // the whole image's mean from the channels' sums: one sum per channel, not a second one over all
    const double all = double(n[0] + n[1] + n[2]);
    if (all > 0) {
        m.rmse = std::sqrt(se / all);
        m.relmse = rel / all;
        m.mean = (sum[0] + sum[1] + sum[2]) / all;
        m.ref_mean = (rsum[0] + rsum[1] + rsum[2]) / all;
    }
    for (int c = 0; c < 3; ++c)
        if (n[c]) {
            m.channel_mean[c] = sum[c] / double(n[c]);
            m.ref_channel_mean[c] = rsum[c] / double(n[c]);
        }
    if (!rgb.empty()) m.sparkle_share = double(m.sparkles) / double(rgb.size() / 3);
    return m;
}

}  // namespace ht
