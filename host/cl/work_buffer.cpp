#include "cl/work_buffer.h"

namespace ht {

WorkBuffer::WorkBuffer(ClContext& cl, size_t bytes) {
    if (cl.info().type == "CPU" && bytes >= kHostBackedFrom) {
        host_.resize(bytes);  // not touched here: the kernels' first writes fault it in
        buffer_ = cl::Buffer(cl.context(), CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, bytes, host_.data());
    } else {
        buffer_ = cl::Buffer(cl.context(), CL_MEM_READ_WRITE, bytes);
    }
}

}  // namespace ht
