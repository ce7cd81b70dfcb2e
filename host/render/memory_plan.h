// Device memory for a render, planned before anything is allocated: the film and the scene must
// each fit in one allocation; the per-pass path buffers are sized to whatever is left (a smaller
// pass means more passes per sample, never a different image).  A render that cannot fit is
// refused with the sizes named, instead of failing half-way in the driver.
#pragma once

#include "bvh/geometry_paging.h"
#include "core/byte_size.h"
#include "render/path_buffers.h"

#include <cstddef>
#include <cstdint>

namespace ht {

struct MemoryPlan {
    size_t paths_per_pass = 0;         // path slots
    size_t camera_paths_per_pass = 0;  // paths_per_pass / the buffers' slots_per_pixel
    uint64_t film_bytes = 0, scene_bytes = 0, pass_bytes = 0;
    GeometryPaging paging;  // as uploaded, for --verbose
};

// pixels: the film's; camera_paths: the most camera paths a pass can use (the traced pixels times
// the samples a pass may render of each); the pass is never planned larger.
// budget: the smaller of the device's global memory and the user's --max-memory (0 = device).
// buffers: the per-path buffers the render allocates (render/path_buffers.h).
// scene_bytes counts every page of the geometry (paging: how it was cut; the scene needs no
// single allocation of its size, only the film does).
// Throws DeviceError (exit 3) when the film or the scene alone cannot fit.
MemoryPlan plan_device_memory(uint64_t pixels, uint64_t camera_paths, uint64_t scene_bytes, uint64_t max_alloc, uint64_t global_mem,
                              uint64_t user_limit, size_t max_paths_per_pass, const PathBufferSet& buffers,
                              const GeometryPaging& paging = {});

}  // namespace ht
