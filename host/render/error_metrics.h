// Image error against a reference: the numbers behind every "run time against error" claim.
#pragma once

#include <cstddef>
#include <vector>

namespace ht {


struct ErrorMetrics {
    double rmse = 0;      // sqrt(mean over pixels and channels of (x - ref)^2)
    double relmse = 0;    // mean of (x - ref)^2 / (ref^2 + 1e-2), robust to dark pixels (Rousselle et al.)
    double max_abs = 0;   // largest |x - ref|
    double mean = 0, ref_mean = 0;
    size_t nonfinite = 0; // NaN/Inf values in the image (counted, excluded from the rest)
};

// rgb and ref hold 3 floats per pixel, same size.
ErrorMetrics compare_images(const std::vector<float>& rgb, const std::vector<float>& ref);

}  // namespace ht
