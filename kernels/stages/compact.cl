/* Stable stream compaction of the extension queue: shade leaves each surviving path's next ray
 * in the slot of the ray it shaded (stage_path[k] = path, or HT_NO_PATH); these three kernels
 * move them to the front, in slot order:
 *   compact_count   -> surviving paths per work-group
 *   compact_scan    -> exclusive prefix over the groups (one work-item; a few thousand adds)
 *   compact_scatter -> each survivor to group offset + rank inside its group
 * The order of the next queue is therefore a function of the previous queue alone, never of
 * thread timing, which keeps every pixel independent of the thread count and the device.
 * All three require the local size HT_COMPACT_GROUP. */
#include "../types.h"

#define HT_COMPACT_GROUP 64u

__kernel __attribute__((reqd_work_group_size(64, 1, 1)))
void compact_count(__global const uint* stage_path, uint count, __global uint* group_sums) {
    __local uint partial[HT_COMPACT_GROUP];
    uint i = get_global_id(0), l = get_local_id(0);
    partial[l] = (i < count && stage_path[i] != HT_NO_PATH) ? 1u : 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint s = HT_COMPACT_GROUP / 2u; s > 0u; s >>= 1) {
        if (l < s) partial[l] += partial[l + s];
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    if (l == 0u) group_sums[get_group_id(0)] = partial[0];
}

__kernel void compact_scan(__global uint* group_sums, uint groups, __global uint* counters) {
    if (get_global_id(0) != 0u) return;
    uint run = 0u;
    for (uint g = 0u; g < groups; ++g) {
        uint c = group_sums[g];
        group_sums[g] = run;
        run += c;
    }
    counters[HT_COUNTER_NEXT] = run;
}

__kernel __attribute__((reqd_work_group_size(64, 1, 1)))
void compact_scatter(__global const HtRay* stage_rays, __global const uint* stage_path, uint count,
                     __global const uint* group_offsets, __global HtRay* out_rays,
                     __global uint* out_path) {
    __local uint scan[2][HT_COMPACT_GROUP];
    uint i = get_global_id(0), l = get_local_id(0);
    uint path = i < count ? stage_path[i] : HT_NO_PATH;
    uint flag = path != HT_NO_PATH ? 1u : 0u;
    /* inclusive Hillis-Steele scan, double-buffered */
    uint src = 0u;
    scan[0][l] = flag;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint off = 1u; off < HT_COMPACT_GROUP; off <<= 1) {
        uint v = scan[src][l] + (l >= off ? scan[src][l - off] : 0u);
        scan[1u - src][l] = v;
        src = 1u - src;
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    if (flag) {
        uint slot = group_offsets[get_group_id(0)] + scan[src][l] - 1u;
        out_rays[slot] = stage_rays[i];
        out_path[slot] = path;
    }
}
