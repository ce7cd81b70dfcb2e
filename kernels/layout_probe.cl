/* Reports the OpenCL compiler's layout of every shared struct (kernels/layouts.h), in list order:
 * out[i] = sizeof or offsetof of entry i.  tests/kernel/layout_test.cpp compares it with the
 * list, which the host compiler checks at build time (host/core/kernel_layouts.cpp). */
#include "layouts.h"

#define HT_PROBE_SIZE(T, bytes) out[i++] = (uint)sizeof(T);
#define HT_PROBE_FIELD(T, field, offset) out[i++] = (uint)__builtin_offsetof(T, field);

__kernel void layout_probe(__global uint* out) {
    if (get_global_id(0) != 0) return;
    uint i = 0;
    HT_SHARED_LAYOUTS(HT_PROBE_SIZE, HT_PROBE_FIELD)
}
