/* Queue append with work-group-aggregated atomics: one global atomic per work-group instead of
 * one per item (docs/POCL.md §3: ~5x faster than a global atomic_inc per survivor).
 * Every work-item of the group must call it (it has barriers); `n` says how many entries it
 * appends (0, 1, or several: shade's light samples at a first vertex).
 * Returns the first slot of this item's entries, or 0xFFFFFFFF if it appended none.
 * Call it once per kernel: two appends in a row through the same __local pair (shade's shadow and
 * cut statistics until 2026-12-02) miscounted on PoCL 3.1 with two threads, by a different few
 * hundred in each run of the same render, while one append counts exactly. */
#ifndef HT_QUEUE_H
#define HT_QUEUE_H

HT_FN uint ht_queue_append(uint n, __local uint* local_count, __local uint* local_base,
                           volatile __global uint* counter) {
    if (get_local_id(0) == 0) *local_count = 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    uint local_slot = n ? atomic_add((volatile __local uint*)local_count, n) : 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (get_local_id(0) == 0) *local_base = *local_count ? atomic_add(counter, *local_count) : 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    return n ? *local_base + local_slot : 0xFFFFFFFFu;
}

#endif
