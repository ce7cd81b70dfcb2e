/* Stage (--indirect afs, last bounce): shadow rays through hair that is treated as translucent.
 *
 * Zinke 2004 §5/§7: beyond the traced bounces, hair-to-hair scattering is approximated by the
 * averaged attenuation coefficients -- light crossing a fibre keeps AFS_TT^avg(theta) of its
 * energy (theta = inclination of the ray to that fibre), as in deep shadow maps / pixel blending
 * with averaged attenuation factors: transmittance[j] = prod AFS_TT over the fibres the ray crosses
 * in (tmin, tmax).
 *
 * AFS_TT^avg(theta) per material comes from a table (fiber/afs.h ht_afs_tt_lookup).
 *
 * A product does not depend on the order of its factors, so one traversal visits every leaf the
 * ray's segment (tmin, tmax) touches and multiplies in each crossing as it comes (an "all hits"
 * traversal: the ray is never shortened), instead of a closest-hit traversal restarted beyond every
 * fibre (the previous version: up to 64 restarts).  It stops as soon as the running transmittance
 * of every channel is below HT_AFS_MIN_TRANSMITTANCE (factors are <= 1, so the final product would
 * be too: the result does not depend on the visiting order) or at the first triangle (meshes are
 * opaque).
 *
 * What counts as one crossing: a capsule the ray intersects, except that a run of consecutive
 * capsules of one strand that the ray all intersects (it enters the next segment at a joint, or runs
 * along a bend) is one crossing, counted at the run's first segment: segment k counts unless the ray
 * also intersects segment k - 1 of the same strand.  That is a local test, so it too is independent
 * of the visiting order.  Entry and exit of one capsule are one intersection test, never two.
 * The previous closest-hit loop skipped to the exit of the hit segment's infinite cylinder and could
 * count the next segment of the same strand a second time (darker where rays run along strands),
 * and ignored crossings after the 64th; both differences are measured in docs/PAPER.md.
 * --indirect dual (Zinke et al. 2008, kernels/fiber/dual.h) walks its shadow rays the same way,
 * with the per-fibre forward attenuation a_f(theta) for AFS_TT and the spread beta_f^2(theta)
 * summed alongside, and counts the crossings (none: the light arrives directly).
 * A program of its own (host/render/renderer.cpp), compiled only with HT_FEATURE_INDIRECT_AFS or
 * HT_FEATURE_INDIRECT_DUAL. */
#include "../types.h"

#if HT_FEATURE_INDIRECT_AFS || HT_FEATURE_INDIRECT_DUAL

#include "../geometry/bvh_traverse.h"
#include "../fiber/afs.h"
#include "../fiber/dual.h"
#include "../integrator/aov_record.h"
#include "stage_args.h"

#define HT_AFS_MIN_TRANSMITTANCE 1e-4f

/* What a translucent shadow ray gathered: transmittance T (0: blocked), and for dual the summed
 * spread and the number of crossings. */
typedef struct {
    float3 T, spread;
    uint crossings;
} HtCrossings;

/* One fibre crossed at inclination theta: the AFS table's AFS_TT (dual = 0) or the dual table's
 * a_f and beta_f^2 (dual = 1). */
HT_FN void ht_cross_fibre(__global const float* table, int dual, uint material, float theta, HtCrossings* c) {
    if (dual) {
        c->T *= ht_dual_row(table, material, theta, HT_DUAL_ROW_AF);
        c->spread += ht_dual_row(table, material, theta, HT_DUAL_ROW_BETA_F2);
        c->crossings += 1u;
    } else {
        c->T *= ht_afs_tt_lookup(table, material, theta);
    }
}

/* Applies the crossings of the leaf [first, first + count) to c; returns 1 when the ray is
 * blocked (a triangle, or T negligible in every channel), with T set to 0. */
HT_FN int ht_afs_leaf(HT_SEGS_PARAM, HT_POINTS_PARAM, __global const uint* strand_material, __global const float* table,
                      int dual, uint first, uint count, float3 o, float3 d, float tmin, float tmax, HtCrossings* c) {
    for (uint k = first; k < first + count; ++k) {
        const HtSegment s = HT_SEG(k);
#if HT_FEATURE_MESHES
        if (ht_seg_flags(s) & HT_SEG_TRIANGLE) {
            float b1, b2;
            const float t = ht_triangle_intersect(o, d, ht_point_pos(HT_POINT(s.point)),
                                                  ht_point_pos(HT_POINT(s.point + 1u)),
                                                  ht_point_pos(HT_POINT(s.point + 2u)), tmin, tmax, &b1, &b2);
            if (t < tmax) {
                c->T = (float3)(0.0f);
                return 1;
            }
            continue;
        }
#endif
        const HtPoint a = HT_POINT(s.point);
        const HtPoint b = HT_POINT(s.point + 1u);
        const float3 pa = ht_point_pos(a), pb = ht_point_pos(b);
        if (!(ht_capsule_intersect(o, d, pa, pb, ht_hit_radius(a, b), ht_seg_flags(s) & HT_SEG_FIRST, tmin, tmax) < tmax))
            continue;
        if (!(ht_seg_flags(s) & HT_SEG_FIRST)) {
            /* the strand's previous segment: points are stored strand by strand.  Its begin sphere
             * (a root's) is left out: a joint is owned by the segment that ends there. */
            const HtPoint z = HT_POINT(s.point - 1u);
            if (ht_capsule_intersect(o, d, ht_point_pos(z), pa, ht_hit_radius(z, a), 0u, tmin, tmax) < tmax)
                continue;
        }
        const float3 u = pb - pa;
        const float len2 = dot(u, u);
        const float3 axis = len2 > 0.0f ? u * rsqrt(len2) : (float3)(1.0f, 0.0f, 0.0f);
        const float theta = asin(clamp(fabs(dot(d, axis)), 0.0f, 1.0f));
        ht_cross_fibre(table, dual, strand_material[ht_seg_strand(s)], theta, c);
        if (max(c->T.x, max(c->T.y, c->T.z)) < HT_AFS_MIN_TRANSMITTANCE) {
            c->T = (float3)(0.0f);
            return 1;
        }
    }
    return 0;
}

/* Walks shadow ray `ray` (tmax > tmin) through the hair; c->T = 0 when it is blocked. */
HT_FN void ht_translucent_shadow(HT_GEOMETRY_PARAMS, __global const uint* strand_material, __global const float* table,
                                 int dual, HtRay ray, HtCrossings* c) {
    const float3 o = (float3)(ray.ox, ray.oy, ray.oz), d = (float3)(ray.dx, ray.dy, ray.dz);
    const float tmin = ray.tmin, tmax = ray.tmax < HT_T_FAR ? ray.tmax : HT_T_FAR;
    c->T = (float3)(1.0f);
    c->spread = (float3)(0.0f);
    c->crossings = 0u;

    /* The slab test of ht_traverse (geometry/bvh_traverse.h) with a fixed far end: every leaf box
     * the segment touches is visited once, in any order. */
    const HtSlabRay slab = ht_slab_ray(o, d);
    uint stack[HT_STACK_SIZE];
    int sp = 0;
    uint cur = 0;
    for (;;) {
        float near[HT_BVH_WIDTH];
        uint leaves;
        HT_CONST_GLOBAL HtBvhNode* n = ht_node_of(HT_NODES_ARG, cur);
        const uint inner = ht_node_test(HT_NODES_ARG, cur, n, o, d, &slab, tmin, tmax, near, &leaves);
        int stop = 0;
        for (uint hit = leaves | inner; hit != 0u && !stop; hit &= hit - 1u) {
            const uint k = ht_lowest_bit(hit);
            if (n->count[k] != 0u)
                stop = ht_afs_leaf(HT_SEGS_ARG, HT_POINTS_ARG, strand_material, table, dual, n->child[k], n->count[k], o,
                                   d, tmin, tmax, c);
            else
                stack[sp++] = n->child[k];
        }
        if (stop || sp == 0) break;
        cur = stack[--sp];
    }
    if (!(ht_isfinite(c->T.x) && ht_isfinite(c->T.y) && ht_isfinite(c->T.z))) c->T = (float3)(0.0f);
}

#if HT_FEATURE_INDIRECT_AFS
__kernel void intersect_shadow_afs(HT_GEOMETRY_PARAMS, __global const uint* strand_material,
                                   __global const float* afs_tt_table, __global const HtRay* rays,
                                   __global float4* transmittance, uint count) {
    uint j = get_global_id(0);
    if (j >= count) return;
    HtRay ray = rays[j];
    if (!(ray.tmax > ray.tmin)) {
        transmittance[j] = (float4)(0.0f);
        return;
    }
    HtCrossings c;
    ht_translucent_shadow(HT_GEOMETRY_ARGS, strand_material, afs_tt_table, 0, ray, &c);
    transmittance[j] = (float4)(c.T, 0.0f);
}

/* Companion of resolve_shadows for translucent shadows: contribution times transmittance. */
__kernel void resolve_shadows_afs(__global const HtShadowContrib* shadow_contrib,
                                  __global const float4* transmittance, uint count,
                                  __global HtPathState* paths HT_RESOLVE_AOV_PARAMS) {
    uint j = get_global_id(0);
    if (j >= count) return;
    float4 T = transmittance[j];
    if (T.x + T.y + T.z <= 0.0f) return;
    HtShadowContrib c = shadow_contrib[j];
    __global HtPathState* s = &paths[c.path];
    s->radiance[0] += c.contrib[0] * T.x;
    s->radiance[1] += c.contrib[1] * T.y;
    s->radiance[2] += c.contrib[2] * T.z;
#if HT_FEATURE_AOVS
    ht_aov_resolve(aovs, shadow_aov, j, c.path, (float3)(c.contrib[0] * T.x, c.contrib[1] * T.y, c.contrib[2] * T.z));
#endif
}

#endif /* HT_FEATURE_INDIRECT_AFS */

#if HT_FEATURE_INDIRECT_DUAL
/* --indirect dual, the camera path's only vertex: shadow ray j's crossings decide what its light
 * sample adds -- none (the light arrives directly): the exact single scattering the shade stage
 * evaluated (shadow_contrib) plus the local back-scattering; some: the global multiple
 * scattering through them plus its back-scattering; blocked: nothing. */
__kernel void shadow_dual(HT_GEOMETRY_PARAMS, __global const uint* strand_material, __global const float* dual_table,
                          __global const HtRay* rays, __global const HtShadowContrib* shadow_contrib,
                          __global const HtDualRecord* records, uint count, __global HtPathState* paths,
                          volatile __global uint* counters) {
    uint j = get_global_id(0);
    if (j >= count) return;
    HtRay ray = rays[j];
    if (!(ray.tmax > ray.tmin)) return;
    HtCrossings c;
    ht_translucent_shadow(HT_GEOMETRY_ARGS, strand_material, dual_table, 1, ray, &c);
    if (!(c.T.x + c.T.y + c.T.z > 0.0f)) return;
    const HtShadowContrib sc = shadow_contrib[j];
    const HtDualRecord r = records[j];
    float3 add = c.crossings == 0u ? (float3)(sc.contrib[0], sc.contrib[1], sc.contrib[2]) : (float3)(0.0f);
    if (r.material != HT_NO_PATH)
        add += (float3)(r.weight[0], r.weight[1], r.weight[2]) *
               ht_dual_eval(dual_table, r.material, r.theta_i, r.theta_o, r.phi, c.crossings, c.T, c.spread);
    if (!(ht_isfinite(add.x) && ht_isfinite(add.y) && ht_isfinite(add.z))) {
        atomic_inc(&counters[HT_COUNTER_NAN]);
        return;
    }
    __global HtPathState* s = &paths[sc.path];
    s->radiance[0] += add.x;
    s->radiance[1] += add.y;
    s->radiance[2] += add.z;
}
#endif /* HT_FEATURE_INDIRECT_DUAL */

#endif /* HT_FEATURE_INDIRECT_AFS || HT_FEATURE_INDIRECT_DUAL */
