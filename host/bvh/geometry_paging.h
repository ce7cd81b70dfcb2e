// Geometry larger than one device allocation: how its arrays are cut into pages.
#pragma once

#include <cstdint>
#include <vector>

namespace ht {

// How the scene's geometry arrays are cut into device buffers (kernels/geometry/pages.h).
// pages == 1: one buffer per array, the kernels' plain single-pointer code.  Otherwise every
// array is cut into `pages` buffers of 2^page_log2 bytes (the last one shorter; an array needing
// fewer pages repeats its last buffer in the unused kernel arguments).
struct GeometryPaging {
    uint32_t pages = 1;
    uint32_t page_log2 = 0;  // 0 when pages == 1
    uint64_t page_bytes() const { return pages > 1 ? uint64_t(1) << page_log2 : 0; }
};
constexpr uint32_t kMaxGeometryPages = 8;  // HT_MAX_GEOMETRY_PAGES

struct GeometryArray {
    const char* name;  // "BVH node", for messages
    uint64_t bytes;
};

// One buffer per array when every array fits in max_alloc (the common case, which then pays
// nothing); otherwise pages of the largest power of two <= max_alloc, as many as the largest
// array needs.  Throws DeviceError (exit 3) naming the array and the sizes when that takes more
// than kMaxGeometryPages.
GeometryPaging plan_geometry_pages(const std::vector<GeometryArray>& arrays, uint64_t max_alloc);

}  // namespace ht
