#include "render/error_metrics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ht {

ErrorMetrics compare_images(const std::vector<float>& rgb, const std::vector<float>& ref) {
    if (rgb.size() != ref.size()) throw std::invalid_argument("image and reference differ in size");
    ErrorMetrics m;
    double se = 0, rel = 0, sum = 0, rsum = 0;
    size_t n = 0;
    for (size_t i = 0; i < rgb.size(); ++i) {
        double x = rgb[i], r = ref[i];
        if (!std::isfinite(x)) { ++m.nonfinite; continue; }
        if (!std::isfinite(r)) continue;
        double d = x - r;
        se += d * d;
        rel += d * d / (r * r + 1e-2);
        m.max_abs = std::max(m.max_abs, std::fabs(d));
        sum += x;
        rsum += r;
        ++n;
    }
    if (n) {
        m.rmse = std::sqrt(se / double(n));
        m.relmse = rel / double(n);
        m.mean = sum / double(n);
        m.ref_mean = rsum / double(n);
    }
    return m;
}

}  // namespace ht
