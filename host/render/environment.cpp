#include "render/environment.h"

#include "core/constants.h"
#include "io/image_io.h"

#include <cmath>

namespace ht {

namespace {
// Build a normalized CDF (n + 1 entries, cdf[0] = 0, cdf[n] = 1) from non-negative weights;
// an all-zero row falls back to uniform so sampling never divides by zero.
void build_cdf(const double* w, size_t n, float* cdf, double* total) {
    double sum = 0;
    for (size_t i = 0; i < n; ++i) sum += w[i];
    *total = sum;
    cdf[0] = 0.0f;
    double run = 0;
    for (size_t i = 0; i < n; ++i) {
        run += sum > 0 ? w[i] : 1.0;
        cdf[i + 1] = float(run / (sum > 0 ? sum : double(n)));
    }
    cdf[n] = 1.0f;
}
}  // namespace

EnvironmentTables build_environment(const Environment& env) {
    EnvironmentTables t;
    HtEnvironment& h = t.header;
    h.enabled = env.enabled() ? 1u : 0u;
    for (int c = 0; c < 3; ++c) h.scale[c] = env.map_path.empty() ? env.color[c] * env.intensity : env.intensity;
    if (env.map_path.empty()) {
        // the kernels still get valid (one-element) tables
        t.texels.assign(4, 0.0f);
        t.marginal = {0.0f, 1.0f};
        t.conditional = {0.0f, 1.0f};
        h.width = h.height = 1;
        return t;
    }
    int w = 0, hgt = 0;
    std::vector<float> rgb;
    try {
        rgb = read_rgb_image(env.map_path, w, hgt);
    } catch (const std::exception& e) {
        throw SceneError(std::string("environment map ") + e.what());
    }
    return build_environment_from_rgb(w, hgt, rgb, env.intensity, env.map_path);
}

EnvironmentTables build_environment_from_rgb(int w, int hgt, const std::vector<float>& rgb, float intensity,
                                             const std::string& name) {
    EnvironmentTables t;
    HtEnvironment& h = t.header;
    h.enabled = 1;
    for (int c = 0; c < 3; ++c) h.scale[c] = intensity;
    if (w < 1 || hgt < 1) throw SceneError(name + ": environment map is empty");
    h.has_map = 1;
    h.width = uint32_t(w);
    h.height = uint32_t(hgt);
    t.texels.resize(4 * size_t(w) * hgt);
    std::vector<double> lum(size_t(w) * hgt);
    for (size_t i = 0; i < size_t(w) * hgt; ++i) {
        for (int c = 0; c < 3; ++c) {
            float v = rgb[3 * i + c];
            if (!std::isfinite(v) || v < 0)
                throw SceneError(name + ": environment map has a negative or non-finite texel at pixel " +
                                 std::to_string(i % w) + "," + std::to_string(i / w));
            t.texels[4 * i + c] = v;
        }
        lum[i] = 0.2126 * rgb[3 * i] + 0.7152 * rgb[3 * i + 1] + 0.0722 * rgb[3 * i + 2];
    }
    t.conditional.resize(size_t(hgt) * (w + 1));
    std::vector<double> row_weight(hgt);
    for (int y = 0; y < hgt; ++y) {
        double total;
        build_cdf(&lum[size_t(y) * w], size_t(w), &t.conditional[size_t(y) * (w + 1)], &total);
        double theta = (y + 0.5) / hgt * kPi;
        row_weight[y] = total * std::sin(theta);
    }
    t.marginal.resize(hgt + 1);
    double total;
    build_cdf(row_weight.data(), size_t(hgt), t.marginal.data(), &total);
    return t;
}

}  // namespace ht
