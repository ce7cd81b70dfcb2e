#include "render/split_choice.h"

#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ht {

int pilot_stride(int width, int height) {
    const double per_pixel = std::sqrt(double(width) * double(height) / kPilotPixels);
    return std::max(kPilotStride, int(std::ceil(per_pixel)));
}

std::vector<uint32_t> pilot_pixels(int width, int height) {
    const int stride = pilot_stride(width, height);
    std::vector<uint32_t> pixels;
    for (int y = 0; y < height; y += stride)
        for (int x = 0; x < width; x += stride) pixels.push_back(uint32_t(y) * uint32_t(width) + uint32_t(x));
    return pixels;
}

uint32_t pilot_seed(uint32_t seed, int half) { return (seed | 0x80000000u) ^ (half ? 0x40000000u : 0u); }

double SplitVariance::fixed() const {
    return std::max(total - split / kPilotSplits, 1e-3 * total) / std::clamp(stratification, 1.0, kMaxStratification);
}

SplitVariance split_variance(const std::vector<float>& moments) {
    SplitVariance v;
    const size_t pixels = moments.size() / 16;
    double total = 0, split = 0, first = 0, first_error = 0;
    size_t used = 0;
    for (size_t i = 0; i < pixels; ++i) {
        const float* m = &moments[16 * i];
        const double n = m[15];  // samples, both halves
        if (!(n >= 4)) continue;
        double y_sq = 0, f_sq = 0, f_err = 0;
        for (int c = 0; c < 3; ++c) {
            y_sq += double(m[c]) * m[c];
            const double f = double(m[4 + c]) + m[8 + c], d = (double(m[4 + c]) - m[8 + c]) / (n / 2);
            f_sq += f * f;
            f_err += d * d / 2;  // E[(a - b)^2] / 2: the squared error of either half's mean
        }
        const double var_y = (m[3] - y_sq / n) / (n - 1), var_f = (m[7] - f_sq / n) / (n - 1);
        const double sp = double(m[11]) / n;
        // a pixel whose float sums went non-finite says nothing; rounding may make a flat pixel's
        // variance a little negative
        if (!std::isfinite(var_y) || !std::isfinite(var_f) || !std::isfinite(f_err) || !std::isfinite(sp)) continue;
        total += std::max(var_y, 0.0);
        split += sp;
        first += std::max(var_f, 0.0);
        first_error += f_err * (n / 2);
        ++used;
    }
    if (used == 0) return v;
    v.total = total / double(used);
    v.split = split / double(used);
    v.stratification = first_error > 0 ? first / first_error : 1.0;
    return v;
}

SplitCost split_cost(const RenderStats& pilot, int splits) {
    SplitCost c;
    const std::vector<BounceStats>& b = pilot.bounces;
    if (b.empty() || b[0].paths == 0) return c;
    const double cameras = double(b[0].paths);
    const double hits = b.size() > 1 ? double(b[1].paths) / splits : 0.0;
    c.c0 = (kMissCost * (cameras - hits) + hits + kShadowCost * double(b[0].shadow_rays)) / cameras;
    double later = 0;
    for (size_t i = 1; i < b.size(); ++i) later += kLaterHitCost * double(b[i].paths) + kShadowCost * double(b[i].shadow_rays);
    c.c1 = later / (cameras * splits);
    return c;
}

int best_splits(const SplitVariance& v, const SplitCost& c) {
    if (!(v.split > 0) || !(c.c1 > 0) || !std::isfinite(v.split) || !std::isfinite(v.total) ||
        !std::isfinite(v.stratification) || !std::isfinite(c.c1))
        return kMinAutoSplits;
    const double fixed = v.fixed();
    int best = kMinAutoSplits;
    double best_work = (c.c0 + best * c.c1) * (fixed + v.split / best);
    for (int n = kMinAutoSplits + 1; n <= kMaxAutoSplits; ++n) {
        const double work = (c.c0 + n * c.c1) * (fixed + v.split / n);
        if (work < best_work) best = n, best_work = work;
    }
    return best;
}

std::string SplitChoice::describe() const {
    char line[256];
    std::snprintf(line, sizeof line,
                  "first-hit splits: auto chose %d (pilot %.2f s: V_split / V_fixed = %.3g with stratification %.3g; "
                  "c1 / c0 = %.3g)",
                  splits, seconds, variance.split / variance.fixed(), variance.stratification, cost.c1 / cost.c0);
    return line;
}

}  // namespace ht
