/* Stage 3: closest hits -> shadow queue + next extension queue.
 *
 * For ray k (path p = ray_path[k]) with hit hits[k] at bounce b (b scatterings behind it):
 *   miss      -> path radiance += throughput * environment (MIS-weighted against the
 *                environment's next-event estimate when the environment takes part in it and the
 *                ray did not come from the camera); ends.
 *   b = max_depth: the ray is the last vertex's BCSDF sample, traced only for the environment
 *                it may see (the MIS partner of that vertex's next-event estimate); meeting a
 *                surface, the path is cut by --max-depth and counted (HT_COUNTER_CUT).
 *   hair hit  -> next-event estimation: one light (or an environment map) picked uniformly, the
 *                fibre's scattering function evaluated for it, and a shadow ray queued carrying
 *                the unoccluded contribution; then the fibre model is sampled for the extension
 *                ray (below max_depth; at the last vertex only when there is an environment),
 *                with Russian roulette from HT_RR_START_BOUNCE bounces on
 *                (kernels/integrator/roulette.h).
 *   triangle  -> (HT_FEATURE_MESHES) a Lambertian surface: the same light pick and MIS, shadow
 *                and extension rays spawned a small offset off the surface on their side of the
 *                geometric normal, cosine-weighted sampling (kernels/surface/lambert.h); the
 *                albedo is baseColorFactor times the base colour texture at the interpolated
 *                TEXCOORD_0 when there is one (HT_FEATURE_TEXTURES, kernels/surface/texture.h).
 * Outputs stay in the slot of the shaded ray: shadow_rays[k] (tmax < 0: none) with
 * shadow_contrib[k], and the extension ray in stage_rays[k] with stage_path[k] = path (or
 * HT_NO_PATH); compact.cl then packs the extension queue in a thread-independent order.
 * Every path ends each call in exactly one of: terminated, continued (stage slot filled). */
#include "../types.h"
#include "../geometry/pages.h"
#include "../rng.h"
#include "../lights.h"
#include "../environment.h"
#include "../queue.h"
#include "../integrator/mis.h"
#include "../integrator/roulette.h"
#include "../integrator/shading_point.h"
#include "../integrator/aov_record.h"
#include "../integrator/aov_lobes.h"
#include "stage_args.h"

#ifndef HT_RR_START_BOUNCE
#define HT_RR_START_BOUNCE 3u
#endif

/* --clamp-indirect: light that scattered at two or more surfaces before reaching the camera (NEE
 * from bounce 1 on, environment hits from bounce 2 on) is capped at HT_CLAMP_INDIRECT in its
 * largest channel, hue kept.  Biased (energy is removed) but bounded variance: narrow fibre lobes
 * lit by small lights make rare, very bright hair-to-hair paths (sparkles at low sample counts).
 * Undefined: compiled out. */
HT_FN float3 ht_clamp_indirect(float3 c, uint scatterings) {
#ifdef HT_CLAMP_INDIRECT
    float m = max(c.x, max(c.y, c.z));
    if (scatterings >= 2u && m > HT_CLAMP_INDIRECT) c *= HT_CLAMP_INDIRECT / m;
#endif
    return c;
}


HT_FN int ht_finite3(float3 v) { return ht_isfinite(v.x) && ht_isfinite(v.y) && ht_isfinite(v.z); }

/* Whether the environment takes part in next-event estimation.  A uniform environment does not:
 * directions drawn uniformly over the sphere rarely land in fibre lobes a few degrees wide, so
 * they add variance and nothing else; BCSDF sampling carries it alone (pbrt-v4 skips its uniform
 * infinite light the same way).  A lat-long map is importance sampled and shares by MIS. */
HT_FN uint ht_env_in_nee(const HtEnvironment* env) { return env->enabled && env->has_map ? 1u : 0u; }

/* Next-event light pick shared by hair and surfaces: one of the lights or the environment map,
 * uniformly; returns 0 when the chosen light gives nothing at p.  ls->pdf is the pdf that BCSDF
 * sampling competes with by MIS: the environment's, and 0 (full weight) for every light, since
 * BCSDF-sampled rays never meet a light's surface here (lights are not in the BVH). */
HT_FN int ht_nee_sample(__global const HtLight* lights, uint light_count, const HtEnvironment* env,
                        __global const float* env_texels, __global const float* env_marginal,
                        __global const float* env_conditional, uint nee_count, uint seed,
                        uint pixel, uint sample, uint bounce, float3 p, HtLightSample* ls) {
    float ul = ht_sample(seed, pixel, sample, bounce, HT_DIM_LIGHT_PICK);
    uint li = min((uint)(ul * (float)nee_count), nee_count - 1u);
    float u = ht_sample(seed, pixel, sample, bounce, HT_DIM_LIGHT_U);
    float v = ht_sample(seed, pixel, sample, bounce, HT_DIM_LIGHT_V);
    if (li < light_count) {
        HtLight light = lights[li];
        int ok = ht_sample_light(&light, p, u, v, ls);
        ls->pdf = 0.0f;
        return ok;
    }
    float3 le;
    float pdf_env;
    int ok = ht_env_sample(env, env_texels, env_marginal, env_conditional, u, v, &ls->wi, &le,
                           &pdf_env);
    ls->distance = HT_REAL_MAX;
    ls->pdf = pdf_env;
    ls->li_over_pdf = ok ? le / pdf_env : (float3)(0.0f);
    return ok;
}

/* The path goes on with throughput nthr along the sampled direction w from origin o: fills the
 * extension ray and the path state.  Returns 0 (path ends) for a zero or non-finite throughput,
 * counting the latter. */
HT_FN int ht_continue_path(HtPathState* st, float3 nthr, float pdf, float3 o, float3 w, HtRay* next_ray,
                           volatile __global uint* counters) {
    if (!ht_finite3(nthr)) {
        atomic_inc(&counters[HT_COUNTER_NAN]);
        return 0;
    }
    if (!(nthr.x + nthr.y + nthr.z > 0.0f)) return 0;
    next_ray->ox = o.x; next_ray->oy = o.y; next_ray->oz = o.z;
    next_ray->dx = w.x; next_ray->dy = w.y; next_ray->dz = w.z;
    next_ray->tmin = 0.0f;
    next_ray->tmax = 1e30f;
    st->throughput[0] = nthr.x; st->throughput[1] = nthr.y; st->throughput[2] = nthr.z;
    st->last_pdf = pdf;
    st->flags &= ~HT_PATH_FROM_CAMERA;
    return 1;
}

/* Russian roulette from HT_RR_START_BOUNCE on. */
HT_FN float3 ht_roulette_at(float3 nthr, uint seed, uint pixel, uint sample, uint bounce) {
    if (bounce + 1u < HT_RR_START_BOUNCE) return nthr;
    return ht_roulette(nthr, ht_sample(seed, pixel, sample, bounce, HT_DIM_RR));
}


__kernel void shade(HT_SEGS_PARAM, HT_POINTS_PARAM, HT_TRIS_PARAM, HT_SCENE_PARAMS, HT_SHADE_QUEUE_PARAMS,
                    HtBounce b HT_SHADE_AOV_PARAMS) {
    const uint seed = b.seed, sample = b.sample, bounce = b.bounce, max_depth = b.max_depth;
    const uint field_mode = b.field_mode;
    const float pixel_angle = b.pixel_angle;
    __local uint lcount, lbase;
    uint k = get_global_id(0);
    int active = k < count;
    int want_shadow = 0, want_next = 0, cut = 0;
    HtRay shadow_ray, next_ray;
    float3 shadow_value = (float3)(0.0f);
    uint p = 0u;
    HtPathState st;
#if HT_FEATURE_AOVS
    float4 shadow_frac = (float4)(0.0f);
#endif

    if (active) {
        p = ray_path[k];
        st = paths[p];
        HtRay ray = rays[k];
        HtHit hit = hits[k];
#if HT_FEATURE_AOVS
        __global float* rec = aovs + (size_t)p * HT_AOV_STRIDE;
        if (bounce == 0u) ht_aov_begin(rec, &hit);
        const float4 frac = ht_aov_fractions(rec);
#endif
        float3 thr = ht_load3(st.throughput);
        float3 dir = (float3)(ray.dx, ray.dy, ray.dz);
        const uint nee_count = light_count + ht_env_in_nee(&env);
        /* the last vertex samples a BCSDF ray too when there is light it can find (the
         * environment), so that both halves of the vertex's MIS estimate are there */
        const uint ext_depth = env.enabled ? max_depth + 1u : max_depth;
        if (hit.segment == HT_NO_HIT) {
            float3 le = ht_env_eval(&env, env_texels, dir);
            float w = 1.0f;
            if (!(st.flags & HT_PATH_FROM_CAMERA) && ht_env_in_nee(&env)) {
                float p_light = ht_env_pdf(&env, env_marginal, env_conditional, dir) / (float)nee_count;
                w = ht_mis_power(st.last_pdf, p_light);
            }
            float3 add = ht_clamp_indirect(thr * le * w, bounce);
            if (ht_finite3(add)) {
                st.radiance[0] += add.x; st.radiance[1] += add.y; st.radiance[2] += add.z;
#if HT_FEATURE_AOVS
                ht_aov_add_light(rec, add, bounce, frac);
#endif
            } else {
                atomic_inc(&counters[HT_COUNTER_NAN]);
            }
        } else if (bounce >= max_depth) {
            cut = 1;
        } else {
            /* without an environment nothing is traced past the last vertex: a path counts as
             * cut when it scatters there */
            cut = bounce + 1u == max_depth && !env.enabled;
            HtSegment seg = HT_SEG(hit.segment);
            HtShadingPoint sp;
#if HT_FEATURE_MESHES
            if (seg.flags & HT_SEG_TRIANGLE)
                ht_surface_point(HT_TRI_SHADING(seg.strand), &ray, &hit, textures, texture_count, texels, &sp);
            else
#endif
                ht_fibre_point(materials[strand_material[seg.strand]], HT_POINT(seg.point),
                               HT_POINT(seg.point + 1u), &ray, &hit, st.flags, bounce, field_mode,
                               pixel_angle, &sp);

            /* next-event estimation */
            if (nee_count > 0u) {
                HtLightSample ls;
                if (ht_nee_sample(lights, light_count, &env, env_texels, env_marginal,
                                  env_conditional, nee_count, seed, st.pixel, sample, bounce,
                                  sp.p, &ls)) {
                    float3 value;
                    float pdf_bsdf = 0.0f;
                    ht_point_eval(&sp, ls.wi, &value, &pdf_bsdf);
                    /* lights that BCSDF sampling can also reach (the environment map) share the
                     * estimate by MIS; the others keep weight 1 */
                    float w = ls.pdf > 0.0f ? ht_mis_power(ls.pdf / (float)nee_count, pdf_bsdf) : 1.0f;
                    float3 c = ht_clamp_indirect(thr * value * ls.li_over_pdf * ((float)nee_count * w),
                                                 bounce + 1u);
                    if (!ht_finite3(c)) {
                        atomic_inc(&counters[HT_COUNTER_NAN]);
                    } else if (c.x + c.y + c.z > 0.0f) {
                        float3 o = ht_point_spawn(&sp, ls.wi);
                        shadow_ray.ox = o.x; shadow_ray.oy = o.y; shadow_ray.oz = o.z;
                        shadow_ray.dx = ls.wi.x; shadow_ray.dy = ls.wi.y; shadow_ray.dz = ls.wi.z;
                        shadow_ray.tmin = 0.0f;
                        shadow_ray.tmax = ht_point_shadow_tmax(&sp, ls.distance);
                        shadow_value = c;
                        want_shadow = shadow_ray.tmax > 0.0f;
#if HT_FEATURE_AOVS
                        shadow_frac = bounce == 0u ? ht_aov_lobe_fractions(&sp, ls.wi) : frac;
#endif
                    }
                }
            }

            /* extension ray (with --aovs, the camera vertex's sample is also its albedo estimate) */
            const int extend = bounce + 1u < ext_depth;
            float3 wi = (float3)(0.0f), weight = (float3)(0.0f);
            float pdf = 0.0f;
            int sampled = 0;
#if HT_FEATURE_AOVS
            const int want_sample = extend || bounce == 0u;
#else
            const int want_sample = extend;
#endif
            if (want_sample)
                sampled = ht_point_sample(&sp, seed, st.pixel, sample, bounce, &wi, &weight, &pdf);
            if (extend && sampled) {
                float3 nthr = ht_roulette_at(thr * weight, seed, st.pixel, sample, bounce);
                want_next = ht_continue_path(&st, nthr, pdf, ht_point_spawn(&sp, wi), wi, &next_ray, counters);
            }
#if HT_FEATURE_AOVS
            if (bounce == 0u && sampled && ht_finite3(weight)) {
                ht_aov_add3(rec, HT_AOV_ALBEDO, weight);
                const float4 f = ht_aov_lobe_fractions(&sp, wi);
                rec[HT_AOV_FRACTIONS] = f.x; rec[HT_AOV_FRACTIONS + 1u] = f.y;
                rec[HT_AOV_FRACTIONS + 2u] = f.z; rec[HT_AOV_FRACTIONS + 3u] = f.w;
            }
#endif
        }
        paths[p] = st;
    }

    /* statistics only: the shadow queue is not compacted, its count is reported */
    ht_queue_append(want_shadow, &lcount, &lbase, &counters[HT_COUNTER_SHADOW]);
    ht_queue_append(cut, &lcount, &lbase, &counters[HT_COUNTER_CUT]);
    if (active) {
        if (!want_shadow) {
            shadow_ray.ox = shadow_ray.oy = shadow_ray.oz = 0.0f;
            shadow_ray.dx = shadow_ray.dy = 0.0f;
            shadow_ray.dz = 1.0f;
            shadow_ray.tmin = 0.0f;
            shadow_ray.tmax = -1.0f;
        }
        shadow_rays[k] = shadow_ray;
        HtShadowContrib sc;
        sc.contrib[0] = shadow_value.x; sc.contrib[1] = shadow_value.y; sc.contrib[2] = shadow_value.z;
        sc.path = p;
        shadow_contrib[k] = sc;
#if HT_FEATURE_AOVS
        __global float* sa = shadow_aov + (size_t)k * HT_SHADOW_AOV_STRIDE;
        sa[0] = shadow_frac.x; sa[1] = shadow_frac.y; sa[2] = shadow_frac.z; sa[3] = shadow_frac.w;
        sa[4] = bounce == 0u ? 1.0f : 0.0f;
#endif
        if (want_next) stage_rays[k] = next_ray;
        stage_path[k] = want_next ? p : HT_NO_PATH;
    }
}
