/* Stage (--indirect afs, last bounce): shadow rays through hair that is treated as translucent.
 *
 * Zinke 2004 §5/§7: beyond the traced bounces, hair-to-hair scattering is approximated by the
 * averaged attenuation coefficients -- light crossing a fibre keeps AFS_TT^avg(theta) of its
 * energy (theta = inclination of the ray to that fibre), as in deep shadow maps / pixel blending
 * with averaged attenuation factors.  Each slot's ray is followed through every fibre it crosses
 * (closest hit, then on from beyond that fibre) and transmittance[j] = prod AFS_TT per crossing.
 * Crossings stop counting once the transmittance is negligible or after HT_AFS_MAX_CROSSINGS.
 * Approximation kept: at a strand joint the next segment may be entered from inside and counted
 * as a second crossing (slightly too dark where rays run along a strand).  Triangles (meshes)
 * block the ray completely. */
#include "../types.h"
#include "../geometry/bvh_traverse.h"
#include "../fiber/afs.h"

#define HT_AFS_MAX_CROSSINGS 64
#define HT_AFS_MIN_TRANSMITTANCE 1e-4f

/* Parameter along the ray where it leaves the infinite cylinder (axis a + s u, radius r). */
HT_FN float ht_cylinder_exit(float3 o, float3 d, float3 a, float3 u, float r, float t_hit) {
    float3 w = (o - a) - dot(o - a, u) * u;
    float3 dp = d - dot(d, u) * u;
    float A = dot(dp, dp), B = dot(w, dp), C = dot(w, w) - r * r;
    if (A < 1e-12f) return t_hit + 2.0f * r;  /* along the axis: step a diameter */
    float disc = B * B - A * C;
    float t1 = (-B + sqrt(max(disc, 0.0f))) / A;
    return max(t1, t_hit) + 1e-3f * r;
}

__kernel void intersect_shadow_afs(HT_GEOMETRY_PARAMS, __global const uint* strand_material,
                                   __global const HtMaterial* materials, __global const HtRay* rays,
                                   __global float4* transmittance, uint count) {
    uint j = get_global_id(0);
    if (j >= count) return;
    HtRay ray = rays[j];
    if (!(ray.tmax > ray.tmin)) {
        transmittance[j] = (float4)(0.0f);
        return;
    }
    float3 o = (float3)(ray.ox, ray.oy, ray.oz), d = (float3)(ray.dx, ray.dy, ray.dz);
    float3 T = (float3)(1.0f);
    for (int n = 0; n < HT_AFS_MAX_CROSSINGS; ++n) {
        HtHit hit;
        ht_trace_closest(HT_GEOMETRY_ARGS, ray, &hit);
        if (hit.segment == HT_NO_HIT || hit.t >= ray.tmax) break;
        HtSegment s = HT_SEG(hit.segment);
#if HT_FEATURE_MESHES
        /* surfaces are opaque: only hair is translucent */
        if (s.flags & HT_SEG_TRIANGLE) {
            T = (float3)(0.0f);
            break;
        }
#endif
        HtMaterial m = materials[strand_material[s.strand]];
        float3 t = (float3)(hit.tx, hit.ty, hit.tz);
        float theta = asin(clamp(fabs(dot(d, t)), 0.0f, 1.0f));
        T.x *= ht_afs_fast(m.eta, m.sigma_a[0], theta, 1);
        T.y *= ht_afs_fast(m.eta, m.sigma_a[1], theta, 1);
        T.z *= ht_afs_fast(m.eta, m.sigma_a[2], theta, 1);
        if (max(T.x, max(T.y, T.z)) < HT_AFS_MIN_TRANSMITTANCE) {
            T = (float3)(0.0f);
            break;
        }
        HtPoint a = HT_POINT(s.point);
        ray.tmin = ht_cylinder_exit(o, d, (float3)(a.x, a.y, a.z), t, hit.radius, hit.t);
        if (!(ray.tmin < ray.tmax)) break;
    }
    if (!(ht_isfinite(T.x) && ht_isfinite(T.y) && ht_isfinite(T.z))) T = (float3)(0.0f);
    transmittance[j] = (float4)(T, 0.0f);
}

/* Companion of resolve_shadows for translucent shadows: contribution times transmittance. */
__kernel void resolve_shadows_afs(__global const HtShadowContrib* shadow_contrib,
                                  __global const float4* transmittance, uint count,
                                  __global HtPathState* paths) {
    uint j = get_global_id(0);
    if (j >= count) return;
    float4 T = transmittance[j];
    if (T.x + T.y + T.z <= 0.0f) return;
    HtShadowContrib c = shadow_contrib[j];
    __global HtPathState* s = &paths[c.path];
    s->radiance[0] += c.contrib[0] * T.x;
    s->radiance[1] += c.contrib[1] * T.y;
    s->radiance[2] += c.contrib[2] * T.z;
}
