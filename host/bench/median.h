// The median of repeated timings: the value the bench reports for every measured case.
#pragma once

#include <algorithm>
#include <vector>

namespace ht {

// The upper median (the middle element of an even count); 0 for no values.
inline double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}

}  // namespace ht
