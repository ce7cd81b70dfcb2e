#include "bvh/geometry_paging.h"

#include "core/byte_size.h"
#include "core/errors.h"
#include "kernels/geometry/pages.h"

namespace ht {

GeometryPaging plan_geometry_pages(const std::vector<GeometryArray>& arrays, uint64_t max_alloc) {
    GeometryPaging g;
    uint64_t largest = 0;
    const GeometryArray* worst = nullptr;
    for (const GeometryArray& a : arrays)
        if (a.bytes > largest) largest = a.bytes, worst = &a;
    if (!max_alloc || largest <= max_alloc) return g;
    // A power of two so the kernels find (page, offset) by shift and mask; at least one record of
    // the largest paged type (HtBvhNode, 256 bytes) per page.
    const uint32_t min_log2 = HT_NODE_BYTES_LOG2;
    const uint64_t min_page = uint64_t(1) << min_log2;
    uint32_t log2 = min_log2;
    while (log2 < 35 && (uint64_t(1) << (log2 + 1)) <= max_alloc) ++log2;
    const uint64_t page = uint64_t(1) << log2;
    const uint64_t pages = (largest + page - 1) / page;
    if (max_alloc < min_page)
        throw DeviceError("the device allocates at most " + format_bytes(max_alloc) + " per buffer, less than one " +
                          std::to_string(min_page) + "-byte geometry record; the scene's " + worst->name +
                          " array needs " + format_bytes(largest));
    if (pages > kMaxGeometryPages)
        throw DeviceError("the scene's " + std::string(worst->name) + " array needs " + format_bytes(largest) +
                          ", which would take " + std::to_string(pages) + " buffers of " + format_bytes(page) +
                          " (the largest power of two within the device's maximum allocation of " +
                          format_bytes(max_alloc) + "); at most " + std::to_string(kMaxGeometryPages) +
                          " buffers per array are supported: use a device with larger allocations or a smaller scene");
    g.pages = uint32_t(pages);
    g.page_log2 = log2;
    return g;
}

}  // namespace ht
