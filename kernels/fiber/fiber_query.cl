/* Float-precision evaluation of the fibre models for `hairtrace fiber eval|sample --precision float`
 * and the kernel tests: one work-item per query, each with its own material. */
#include "bcsdf.h"
#include "query.h"

__kernel void fiber_eval(__global const HtMaterial* mats, __global const HtFiberQuery* qs,
                         __global HtFiberResult* out, uint n) {
    uint i = get_global_id(0);
    if (i >= n) return;
    HtMaterial m = mats[i];
    HtFiberQuery q = qs[i];
    float3 lobes[4];
    float3 value;
    float pdf;
    ht_bcsdf_eval_lobes(&m, (float3)(q.wo[0], q.wo[1], q.wo[2]), (float3)(q.wi[0], q.wi[1], q.wi[2]), q.h,
                        lobes, &value, &pdf);
    HtFiberResult r;
    r.value[0] = value.x; r.value[1] = value.y; r.value[2] = value.z; r.value[3] = 0.0f;
    for (int p = 0; p < 4; ++p) {
        r.lobes[p][0] = lobes[p].x; r.lobes[p][1] = lobes[p].y; r.lobes[p][2] = lobes[p].z; r.lobes[p][3] = 0.0f;
    }
    r.wi[0] = 0.0f; r.wi[1] = 0.0f; r.wi[2] = 0.0f; r.wi[3] = 0.0f; /* eval: unused */
    r.pdf = pdf; r.ok = 1.0f; r.pad0 = 0.0f; r.pad1 = 0.0f;
    out[i] = r;
}

__kernel void fiber_sample(__global const HtMaterial* mats, __global const HtFiberQuery* qs,
                           __global HtFiberResult* out, uint n) {
    uint i = get_global_id(0);
    if (i >= n) return;
    HtMaterial m = mats[i];
    HtFiberQuery q = qs[i];
    float3 wi, weight;
    float pdf;
    int ok = ht_bcsdf_sample_mode(&m, (float3)(q.wo[0], q.wo[1], q.wo[2]), q.h, q.u0, q.u1, q.u2, q.u3,
                                  q.lobe_weight != 0.0f ? 0 : 1, &wi, &weight, &pdf);
    HtFiberResult r;
    r.value[0] = weight.x; r.value[1] = weight.y; r.value[2] = weight.z; r.value[3] = 0.0f;
    for (int p = 0; p < 4; ++p) { r.lobes[p][0] = 0.0f; r.lobes[p][1] = 0.0f; r.lobes[p][2] = 0.0f; r.lobes[p][3] = 0.0f; }
    r.wi[0] = wi.x; r.wi[1] = wi.y; r.wi[2] = wi.z; r.wi[3] = 0.0f;
    r.pdf = pdf; r.ok = (float)ok; r.pad0 = 0.0f; r.pad1 = 0.0f;
    out[i] = r;
}

#include "afs.h"

/* AFS^avg in float: in[i] = (eta, sigma_a, theta [rad], p as float 0..3), out[i] = ht_afs_fast. */
__kernel void fiber_afs(__global const float4* in, __global float* out, uint n) {
    uint i = get_global_id(0);
    if (i >= n) return;
    float4 a = in[i];
    out[i] = ht_afs_fast(a.x, a.y, a.z, (int)a.w);
}
