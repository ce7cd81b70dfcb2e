#include "render/adaptive.h"

#include <algorithm>
#include <cmath>

namespace ht {

namespace {
double luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }
}  // namespace

float error_floor(const Film& film) {
    const size_t pixels = size_t(film.width) * size_t(film.height);
    double sum = 0;
    for (size_t i = 0; i < pixels; ++i)
        sum += luminance(film.mean(i, 0), film.mean(i, 1), film.mean(i, 2));
    return pixels ? float(kAdaptiveEpsShare * sum / double(pixels)) : 0.0f;
}

float pixel_error(const Film& film, size_t i, float eps) {
    if (film.even.empty()) return 0.0f;
    const float* all = &film.rgba[4 * i];
    const float* even = &film.even[4 * i];
    const double n = all[3], n_even = even[3], n_odd = n - n_even;
    if (n_even < 1 || n_odd < 1) return 0.0f;
    const double y_all = luminance(all[0], all[1], all[2]);
    const double y_even = luminance(even[0], even[1], even[2]);
    const double a = y_even / n_even, b = (y_all - y_even) / n_odd;
    const double denominator = 2.0 * (y_all / n + double(eps));
    return denominator > 0 ? float(std::fabs(a - b) / denominator) : 0.0f;
}

AdaptiveState assess_film(const Film& film, int samples, float target) {
    AdaptiveState st;
    const int w = film.width, h = film.height;
    const float eps = error_floor(film);
    const size_t pixels = size_t(w) * size_t(h);
    st.min_spp = pixels ? int(film.rgba[3]) : 0;
    double spp_sum = 0, sq_sum = 0;
    for (size_t i = 0; i < pixels; ++i) {
        const int n = int(film.rgba[4 * i + 3]);
        st.min_spp = std::min(st.min_spp, n);
        st.max_spp = std::max(st.max_spp, n);
        spp_sum += n;
    }
    st.mean_spp = pixels ? spp_sum / double(pixels) : 0.0;
    std::vector<uint8_t> go(pixels, 0);
    for (int ty = 0; ty < h; ty += kAdaptiveTile)
        for (int tx = 0; tx < w; tx += kAdaptiveTile) {
            const int y1 = std::min(ty + kAdaptiveTile, h), x1 = std::min(tx + kAdaptiveTile, w);
            double sum = 0;
            bool complete = true;
            for (int y = ty; y < y1; ++y)
                for (int x = tx; x < x1; ++x) {
                    const size_t i = size_t(y) * size_t(w) + size_t(x);
                    const double e = pixel_error(film, i, eps);
                    sum += e * e;
                    complete = complete && int(film.rgba[4 * i + 3]) == samples;
                }
            const double error = std::sqrt(sum / double((y1 - ty) * (x1 - tx)));
            ++st.tiles;
            st.max_error = std::max(st.max_error, error);
            sq_sum += error * error;
            if (!(error > double(target))) continue;
            ++st.tiles_above;
            if (!complete) continue;
            ++st.active_tiles;
            for (int y = ty; y < y1; ++y)
                for (int x = tx; x < x1; ++x) go[size_t(y) * size_t(w) + size_t(x)] = 1;
        }
    st.rms_error = st.tiles ? std::sqrt(sq_sum / st.tiles) : 0.0;
    for (size_t i = 0; i < pixels; ++i)
        if (go[i]) st.pixels.push_back(uint32_t(i));
    return st;
}

}  // namespace ht
