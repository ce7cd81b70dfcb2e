#include "render/memory_plan.h"

#include "cl/device.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <stdexcept>

namespace ht {

std::string format_bytes(uint64_t b) {
    char s[64];
    if (b >= (uint64_t(1) << 30)) std::snprintf(s, sizeof s, "%.2f GiB", double(b) / double(uint64_t(1) << 30));
    else if (b >= (uint64_t(1) << 20)) std::snprintf(s, sizeof s, "%.1f MiB", double(b) / double(1 << 20));
    else std::snprintf(s, sizeof s, "%llu bytes", (unsigned long long)b);
    return s;
}

uint64_t parse_bytes(const std::string& text) {
    if (text.empty()) throw std::invalid_argument("empty size");
    size_t pos = 0;
    double v = std::stod(text, &pos);
    std::string unit = text.substr(pos);
    for (char& c : unit) c = char(std::toupper((unsigned char)c));
    if (!unit.empty() && unit.back() == 'B') unit.pop_back();
    if (!unit.empty() && unit.back() == 'I') unit.pop_back();
    double scale = 1;
    if (unit == "K") scale = 1024.0;
    else if (unit == "M") scale = 1024.0 * 1024;
    else if (unit == "G") scale = 1024.0 * 1024 * 1024;
    else if (unit == "T") scale = 1024.0 * 1024 * 1024 * 1024;
    else if (!unit.empty()) throw std::invalid_argument("unknown size unit in '" + text + "'");
    if (!(v > 0) || v * scale > 1.8e19) throw std::invalid_argument("size out of range: '" + text + "'");
    return uint64_t(v * scale);
}

GeometryPaging plan_geometry_pages(const std::vector<GeometryArray>& arrays, uint64_t max_alloc) {
    GeometryPaging g;
    uint64_t largest = 0;
    const GeometryArray* worst = nullptr;
    for (const GeometryArray& a : arrays)
        if (a.bytes > largest) largest = a.bytes, worst = &a;
    if (!max_alloc || largest <= max_alloc) return g;
    // A power of two so the kernels find (page, offset) by shift and mask; at least one 128-byte
    // record (the largest paged record, HtTriangleShading) per page.
    uint32_t log2 = 7;
    while (log2 < 35 && (uint64_t(1) << (log2 + 1)) <= max_alloc) ++log2;
    const uint64_t page = uint64_t(1) << log2;
    const uint64_t pages = (largest + page - 1) / page;
    if (max_alloc < 128)
        throw DeviceError("the device allocates at most " + format_bytes(max_alloc) +
                          " per buffer, less than one 128-byte geometry record; the scene's " + worst->name +
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

MemoryPlan plan_device_memory(uint64_t pixels, uint64_t scene_bytes, uint64_t max_alloc, uint64_t global_mem,
                              uint64_t user_limit, size_t max_paths_per_pass, const GeometryPaging& paging) {
    MemoryPlan p;
    p.paging = paging;
    const uint64_t budget = user_limit ? std::min(user_limit, global_mem) : global_mem;
    p.film_bytes = pixels * 16;
    p.scene_bytes = scene_bytes;
    if (p.film_bytes > max_alloc)
        throw DeviceError("the film (" + std::to_string(pixels) + " pixels, " + format_bytes(p.film_bytes) +
                          ") exceeds the device's largest allocation (" + format_bytes(max_alloc) +
                          "); render a smaller image or split it into parts");
    const uint64_t fixed = p.film_bytes + p.scene_bytes;
    // at least one work-group's worth of paths must fit besides the film and the scene
    const uint64_t min_pass = 64 * kBytesPerPath;
    if (fixed + min_pass > budget)
        throw DeviceError("the render needs " + format_bytes(fixed + min_pass) + " of device memory (film " +
                          format_bytes(p.film_bytes) + ", scene " + format_bytes(p.scene_bytes) +
                          (paging.pages > 1 ? " in " + std::to_string(paging.pages) + " pages of " +
                                                  format_bytes(paging.page_bytes()) + " per array"
                                            : std::string()) +
                          ") but only " + format_bytes(budget) + " is available" +
                          (user_limit ? " under --max-memory" : ""));
    uint64_t paths = std::min<uint64_t>({pixels, max_paths_per_pass, (budget - fixed) / kBytesPerPath,
                                         max_alloc / kLargestPathRecord});
    paths = std::max<uint64_t>(paths, 1);
    p.paths_per_pass = size_t(paths);
    p.pass_bytes = paths * kBytesPerPath;
    return p;
}

}  // namespace ht
