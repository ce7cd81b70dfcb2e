// Device memory for a render, planned before anything is allocated: the film and the scene must
// each fit in one allocation; the per-pass path buffers are sized to whatever is left (a smaller
// pass means more passes per sample, never a different image).  A render that cannot fit is
// refused with the sizes named, instead of failing half-way in the driver.
#pragma once

#include "bvh/geometry_paging.h"
#include "core/byte_size.h"

#include <cstddef>
#include <cstdint>

namespace ht {

// Bytes of device memory one in-flight path needs across all wavefront buffers.
constexpr size_t kBytesPerPath = 2 * (32 + 4) /* ray queues + path ids */ + 32 /* hit */ +
                                 48 /* path state */ + 32 + 16 + 4 /* shadow ray, contribution, flag */ +
                                 32 + 4 /* uncompacted extension ray + path */ + 16 /* AFS transmittance */ +
                                 4 /* per-group counts, rounded up */;
constexpr size_t kLargestPathRecord = 48;  // HtPathState: bounds paths per buffer by max_alloc

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

}  // namespace ht
