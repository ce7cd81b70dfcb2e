// A read-write device buffer that the kernels fill, such as the wavefront's per-path state
// (render/path_buffers.h).  On a CPU device the buffer's memory is the host's own, 2 MiB-aligned and
// advised as huge pages (core/bulk_vector.h), handed to the runtime with CL_MEM_USE_HOST_PTR, which
// PoCL's CPU driver takes as the buffer itself: the kernels' first writes then fault in one 2 MiB
// page at a time instead of the runtime's own 4 KiB pages, each a fault of several us on a virtual
// machine (about 30,000 in a 256x256, 16-spp render of pbrt's lock: docs/PERFORMANCE.md section 3
// "Path buffers in huge pages").  Smaller buffers and other devices get the runtime's memory.
// The owner must let the queue finish before it drops or replaces a WorkBuffer that commands may
// still use: the host memory goes with it at once, not when those commands are done.
#pragma once

#include "cl/device.h"
#include "core/bulk_vector.h"

#include <cstddef>

namespace ht {

class WorkBuffer {
public:
    WorkBuffer() = default;
    // Throws cl::Error as clCreateBuffer does.
    WorkBuffer(ClContext& cl, size_t bytes);

    WorkBuffer(WorkBuffer&& o) noexcept = default;
    // The buffer is released before the memory it may use.
    WorkBuffer& operator=(WorkBuffer&& o) noexcept {
        buffer_ = cl::Buffer();
        host_ = std::move(o.host_);
        buffer_ = std::move(o.buffer_);
        return *this;
    }

    cl::Buffer& buffer() { return buffer_; }
    // Whether the buffer lives in the host memory above (for tests).
    bool host_backed() const { return !host_.empty(); }

    // From this size on a CPU device's buffers are host memory: below it an allocation is not
    // huge-page aligned (BulkAllocator), so there is nothing to gain.
    static constexpr size_t kHostBackedFrom = BulkAllocator<unsigned char>::kHugePage;

private:
    BulkVector<unsigned char> host_;  // empty unless the buffer uses it
    cl::Buffer buffer_;               // declared after host_, so released before it
};

}  // namespace ht
