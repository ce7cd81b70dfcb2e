#include "render/memory_plan.h"

#include "core/byte_size.h"
#include "core/errors.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <stdexcept>

namespace ht {

MemoryPlan plan_device_memory(uint64_t pixels, uint64_t camera_paths, uint64_t scene_bytes, uint64_t max_alloc, uint64_t global_mem,
                              uint64_t user_limit, size_t max_paths_per_pass, const PathBufferSet& buffers,
                              const GeometryPaging& paging) {
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
    const uint64_t min_pass = buffers.pass_bytes(kPathGroup);
    if (fixed + min_pass > budget)
        throw DeviceError("the render needs " + format_bytes(fixed + min_pass) + " of device memory (film " +
                          format_bytes(p.film_bytes) + ", scene " + format_bytes(p.scene_bytes) +
                          (paging.pages > 1 ? " in " + std::to_string(paging.pages) + " pages of " +
                                                  format_bytes(paging.page_bytes()) + " per array"
                                            : std::string()) +
                          ") but only " + format_bytes(budget) + " is available" +
                          (user_limit ? " under --max-memory" : ""));
    // pass_bytes is linear in whole work-groups: count in groups, then take the largest that fits
    const uint64_t avail = budget - fixed;
    const uint64_t group_bytes = buffers.pass_bytes(2 * kPathGroup) - buffers.pass_bytes(kPathGroup);
    const uint64_t fit_groups = 1 + (avail - min_pass) / group_bytes;
    const uint64_t per_pixel = buffers.slots_per_pixel;
    uint64_t paths = std::min<uint64_t>({std::max<uint64_t>(camera_paths, 1) * per_pixel, max_paths_per_pass, fit_groups * kPathGroup,
                                         max_alloc / buffers.largest_element()});
    p.camera_paths_per_pass = size_t(std::max<uint64_t>(paths / per_pixel, 1));
    p.paths_per_pass = p.camera_paths_per_pass * per_pixel;
    p.pass_bytes = buffers.pass_bytes(p.paths_per_pass);
    return p;
}

}  // namespace ht
