// Shared helpers of the tests that render through the library and compare films statistically
// (header only: the test globs take *.cpp): one OpenCL context for the test binary, a strand of
// few thick fibres, small render settings, the image mean and the RMSE between two films over rgb.
#pragma once

#include "cl/device.h"
#include "core/film.h"
#include "render/renderer.h"
#include "scene/scene.h"

#include <cmath>
#include <cstddef>

namespace rendertest {

inline ht::ClContext& context() {
    static ht::ClContext cl;  // PoCL start-up is not free
    return cl;
}

// Few, thick fibres: pixels that a fibre covers in part (where stratified jitter pays most), and
// much of the light at depth 3 has crossed hair.
inline ht::Scene thick_strand() {
    ht::Scene s = ht::load_scene("builtin:strand?hairs=150&segments=20&radius=0.8");
    ht::ensure_camera_and_light(s);
    return s;
}

// Few fibres that leave most pixels empty, with a coloured background for those pixels to show
// (render/pixel_footprint.h skips them).
inline ht::Scene sparse_strand() {
    ht::Scene s = ht::load_scene("builtin:strand?hairs=40&segments=12");
    ht::ensure_camera_and_light(s);
    s.environment.color = {0.3f, 0.45f, 0.7f};
    return s;
}

// 48 x 48 pixels: enough for image statistics, quick at a thousand samples.
inline ht::RenderSettings small_settings(int spp, uint32_t seed, int depth) {
    ht::RenderSettings rs;
    rs.width = rs.height = 48;
    rs.spp = spp;
    rs.seed = seed;
    rs.max_depth = depth;
    return rs;
}

// stats: when given, receives the render's statistics (rays, paths).
inline ht::Film render(const ht::Scene& scene, const ht::RenderSettings& rs, ht::RenderStats* stats = nullptr) {
    ht::Film film;
    ht::Renderer r(context(), scene, rs);
    r.render(film);
    if (stats) *stats = r.stats();
    return film;
}

// A reference for an estimator's statistical tests: rs rendered with independent numbers (no
// stratification shared with the estimator under test).
inline ht::Film independent_reference(const ht::Scene& scene, ht::RenderSettings rs) {
    rs.sampler = ht::RenderSettings::Sampler::Independent;
    return render(scene, rs);
}

inline double image_mean(const ht::Film& f) {
    double s = 0;
    for (size_t i = 0; i < size_t(f.width) * f.height; ++i)
        for (int c = 0; c < 3; ++c) s += f.mean(i, c);
    return s / (3.0 * f.width * f.height);
}

inline double rmse(const ht::Film& a, const ht::Film& b) {
    double s = 0;
    const size_t n = size_t(a.width) * a.height;
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) s += std::pow(double(a.mean(i, c)) - b.mean(i, c), 2);
    return std::sqrt(s / (3.0 * n));
}

}  // namespace rendertest
