// Device memory for a render, planned before anything is allocated: the film and the scene must
// each fit in one allocation; the per-pass path buffers are sized to whatever is left (a smaller
// pass means more passes per sample, never a different image).  A render that cannot fit is
// refused with the sizes named, instead of failing half-way in the driver.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ht {

// Bytes of device memory one in-flight path needs across all wavefront buffers.
constexpr size_t kBytesPerPath = 2 * (32 + 4) /* ray queues + path ids */ + 32 /* hit */ +
                                 48 /* path state */ + 32 + 16 + 4 /* shadow ray, contribution, flag */ +
                                 32 + 4 /* uncompacted extension ray + path */ + 16 /* AFS transmittance */ +
                                 4 /* per-group counts, rounded up */;
constexpr size_t kLargestPathRecord = 48;  // HtPathState: bounds paths per buffer by max_alloc

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

struct MemoryPlan {
    size_t paths_per_pass = 0;
    uint64_t film_bytes = 0, scene_bytes = 0, pass_bytes = 0;
    GeometryPaging paging;  // as uploaded, for --verbose
};

// budget: the smaller of the device's global memory and the user's --max-memory (0 = device).
// scene_bytes counts every page of the geometry (paging: how it was cut; the scene needs no
// single allocation of its size, only the film does).
// Throws DeviceError (exit 3) when the film or the scene alone cannot fit.
MemoryPlan plan_device_memory(uint64_t pixels, uint64_t scene_bytes, uint64_t max_alloc, uint64_t global_mem,
                              uint64_t user_limit, size_t max_paths_per_pass, const GeometryPaging& paging = {});

// "1.5 GiB"
std::string format_bytes(uint64_t bytes);

// "512M", "8G", "1073741824" -> bytes; throws std::invalid_argument.
uint64_t parse_bytes(const std::string& text);

}  // namespace ht
