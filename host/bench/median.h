// The medians the bench reports: of repeated timings, and of a tracer's speed against a yardstick
// timed in passes paired with its own.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace ht {

// The upper median (the middle element of an even count); 0 for no values.
inline double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}

// How many times faster than the yardstick, from passes timed in pairs: the median over k of
// theirs_ms[k] / ours_ms[k], pairs without a positive finite time on both sides left out (0 if
// none is left).  A pair runs within a second, so a slow drift of the machine's speed (other
// guests, clocks) slows both of its passes alike and cancels in its ratio, where the ratio of two
// medians taken a block of passes apart carries that drift whole.
inline double paired_speedup(const std::vector<double>& theirs_ms, const std::vector<double>& ours_ms) {
    std::vector<double> ratios;
    for (size_t k = 0; k < std::min(theirs_ms.size(), ours_ms.size()); ++k) {
        const double a = theirs_ms[k], b = ours_ms[k];
        if (std::isfinite(a) && std::isfinite(b) && a > 0 && b > 0) ratios.push_back(a / b);
    }
    return median(ratios);
}

}  // namespace ht
