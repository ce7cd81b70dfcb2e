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
 *   first vertex of a camera path: the camera ray, its hit and the shading point are made once,
 *                the next-event estimate M times (--first-hit-light-samples M) and the extension
 *                N times (--first-hit-splits N, N continuations), each with 1/M or 1/N of the
 *                weight and random numbers of its own (kernels/rng.h).  Continuation j and light
 *                sample j belong to path state p + j, the slots after the camera path's (which is
 *                continuation 0; generate_camera_rays.cl lays them out, accumulate.cl adds them
 *                up).  Hair-to-hair light, the bulk of the variance in a lit lock, is then sampled
 *                N times per camera sample, at N times the cost of the later bounces only.
 *   triangle  -> (HT_FEATURE_MESHES) a Lambertian surface: the same light pick and MIS, shadow
 *                and extension rays spawned a small offset off the surface on their side of the
 *                geometric normal, cosine-weighted sampling (kernels/surface/lambert.h); the
 *                albedo is baseColorFactor times the base colour texture at the interpolated
 *                TEXCOORD_0 when there is one (HT_FEATURE_TEXTURES, kernels/surface/texture.h).
 * Outputs stay in the slot of the shaded ray: shadow_rays[k] (tmax < 0: none) with
 * shadow_contrib[k], and the extension ray in stage_rays[k] with stage_path[k] = path (or
 * HT_NO_PATH) -- at a first vertex in shadow slots k M .. k M + M - 1 and stage slots
 * k N .. k N + N - 1; compact.cl then packs the extension queue in a thread-independent order.
 * Every path ends each call in exactly one of: terminated, continued (stage slot filled). */
/* The fibre models' helpers are force-inlined here (kernels/compat.h): the shade stage evaluates a
 * model twice per vertex (the light estimate, then the sample), and inlined, PoCL shares what the
 * two have in common and keeps the work-group loop whole.  0.93x the CPU of a demo render, 0.96x of
 * pbrt's lock, for about 1.5 s more of the first, uncached build of a marschner/zinke shade
 * program (docs/PERFORMANCE.md section 2). */
#define HT_FIBER_INLINE 1
#include "../types.h"
#include "../geometry/pages.h"
#include "../rng.h"
#include "../lights.h"
#include "../environment.h"
#include "../queue.h"
#include "../integrator/mis.h"
#include "../integrator/roulette.h"
#include "../integrator/shading_point.h"
#ifdef HT_LIGHT_GUIDE
#include "../integrator/light_guide.h"
#endif
#ifdef HT_LIGHT_VERTICES
#include "../integrator/light_vertices.h"
#endif
#include "../integrator/aov_record.h"
#include "../integrator/aov_lobes.h"
#include "stage_args.h"

/* Roulette decides the rays of bounce 4 on (the fourth vertex's continuation).  From bounce 3
 * on, as until session 19, pbrt's lock at depth 5 took 1.15x the time to pbrt's error: a path cut
 * two vertices before --max-depth saves little work, and its survivors' doubled weights cost
 * more (docs/PERFORMANCE.md section 8 "Roulette from the fourth vertex").
 * The continuation into the last vertex (bounce + 2 == max_depth) is judged at
 * HT_RR_LAST_VERTEX_SCALE times its throughput when the light threshold is on: that vertex's only
 * light is its next-event estimate, which the light threshold's roulette (roulette.h
 * ht_light_roulette) judges again after the BCSDF is evaluated towards the light.  A roulette on
 * the ray before it, judged by the throughput alone, ends the estimates that meet a lobe's peak as
 * often as the faint ones, and its survivors' weights grow; with no roulette there the faint last
 * vertices are traced and shaded for nothing.  Measured with the scale 1 (as before), 2, 4, 8 and
 * no roulette there (docs/PERFORMANCE.md section 8 "The roulette into the last vertex"): 4 took
 * pbrt's lock at depth 5 to pbrt's error in 0.89x the time and made builtin:ball 1.09x as
 * efficient, the demo and straight.hair 0.98x; no roulette gained as much on the lock but lost 7-10 %
 * on the other two. */
#ifndef HT_RR_START_BOUNCE
#define HT_RR_START_BOUNCE 4u
#endif
#define HT_RR_LAST_VERTEX_SCALE 4.0f

/* --clamp-indirect: light that scattered at two or more surfaces before reaching the camera (NEE
 * from bounce 1 on, environment hits from bounce 2 on) is capped at HT_CLAMP_INDIRECT in its
 * largest channel, hue kept.  Biased (energy is removed) but bounded variance: narrow fibre lobes
 * lit by small lights make rare, very bright hair-to-hair paths (sparkles at low sample counts).
 * Such light always comes through a continuation, which carries `share` (1/N) of its camera
 * sample: the cap is on what it stands for, c / share, so splits leave the bias as it was.
 * Undefined: compiled out. */
HT_FN float3 ht_clamp_indirect(float3 c, uint scatterings, float share) {
#ifdef HT_CLAMP_INDIRECT
    float m = ht_max_channel(c);
    if (scatterings >= 2u && m > HT_CLAMP_INDIRECT * share) c *= HT_CLAMP_INDIRECT * share / m;
#endif
    return c;
}


HT_FN int ht_finite3(float3 v) { return ht_isfinite(v.x) && ht_isfinite(v.y) && ht_isfinite(v.z); }

/* Whether the environment takes part in next-event estimation.  A uniform environment does not:
 * directions drawn uniformly over the sphere rarely land in fibre lobes a few degrees wide, so
 * they add variance and nothing else; BCSDF sampling carries it alone (pbrt-v4 skips its uniform
 * infinite light the same way).  A lat-long map is importance sampled and shares by MIS. */
HT_FN uint ht_env_in_nee(const HtEnvironment* env) { return env->enabled && env->has_map ? 1u : 0u; }

/* Next-event light pick shared by hair and surfaces: one of the lights or the environment map;
 * returns 0 when the chosen light gives nothing at p, and the pick's inverse probability in
 * *inv_pick.  ls->pdf is the pdf that BCSDF sampling competes with by MIS: the environment's, and
 * 0 (full weight) for every light, since BCSDF-sampled rays never meet a light's surface here
 * (lights are not in the BVH).
 * Estimate `stratum` of `strata` at one vertex picks uniformly from its own 1/strata of [0, 1):
 * M estimates of M lights meet each light once, whatever the sampler.  A single estimate picks
 * uniformly too, or with HT_LIGHT_PICK_IMPORTANCE (--light-pick importance, two lights or more)
 * the lights' share of the choice goes by what each light delivers to p unshadowed
 * (kernels/lights.h ht_pick_light): no estimate is spent on a light that cannot reach p, and a
 * faint light is met as rarely as it matters.  The environment keeps its uniform share, so that
 * the MIS weight of a BCSDF ray that meets it (its pick probability 1 / nee_count) stays as it
 * was. */
HT_FN int ht_nee_sample(__global const HtLight* lights, uint light_count, const HtEnvironment* env,
                        __global const float* env_texels, __global const float* env_marginal,
                        __global const float* env_conditional, uint nee_count, uint seed,
                        uint pixel, uint sample, uint bounce, uint stratum, uint strata,
                        const HtShadingPoint* sp, HtLightSample* ls, float* inv_pick, uint* picked) {
    const float3 p = sp->p;
    /* Draws only where they decide something (a Sobol' draw is not free, and no other draw depends
     * on whether one was made): the pick among two or more, the direction for a sphere light or
     * the environment map (the delta lights ignore u and v). */
    const float ul = nee_count > 1u
                         ? ((float)stratum + ht_sample(seed, pixel, sample, bounce, HT_DIM_LIGHT_PICK)) / (float)strata
                         : 0.0f;
    uint li;
    *inv_pick = (float)nee_count;
#ifdef HT_LIGHT_PICK_IMPORTANCE
    if (strata == 1u && light_count >= 2u && light_count <= HT_LIGHT_PICK_MAX) {
        /* [0, light_count / nee_count) of ul goes to the lights, by importance; the rest is the
         * environment's */
        const float lights_share = (float)light_count / (float)nee_count;
        if (ul < lights_share) {
            float inv_q;
            li = ht_pick_light(lights, light_count, p, sp->is_surface ? sp->ng : sp->tangent, sp->is_surface,
                               ul / lights_share, &inv_q);
            if (li == light_count) return 0;
            *inv_pick = inv_q / lights_share;
        } else {
            li = light_count;
        }
    } else
#endif
        li = min((uint)(ul * (float)nee_count), nee_count - 1u);
    *picked = li;
    float u = 0.5f, v = 0.5f;
#if HT_FEATURE_LIGHT_SPHERE
    if (li >= light_count || lights[li].type == HT_LIGHT_SPHERE) {
#else
    if (li >= light_count) {
#endif
        ht_sample2(seed, pixel, sample, bounce, HT_DIM_LIGHT_U, HT_DIM_LIGHT_V, &u, &v);
    }
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
HT_FN int ht_continue_path(HtPathState* st, float3 nthr, float pdf, float3 o, float3 w, int from_fibre,
                           HtRay* next_ray, volatile __global uint* counters) {
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
    st->flags = (st->flags & ~(HT_PATH_FROM_CAMERA | HT_PATH_FROM_FIBRE)) | (from_fibre ? HT_PATH_FROM_FIBRE : 0u);
    return 1;
}

/* Russian roulette from HT_RR_START_BOUNCE on, for a continuation carrying `share` of its camera
 * sample; the continuation into the last vertex judged as above. */
HT_FN float3 ht_roulette_at(float3 nthr, float share, uint seed, uint pixel, uint sample, uint bounce,
                            uint max_depth) {
    if (bounce + 1u < HT_RR_START_BOUNCE) return nthr;
    float judged_share = share;
#ifdef HT_LIGHT_THRESHOLD
    if (bounce + 2u == max_depth) judged_share = share / HT_RR_LAST_VERTEX_SCALE;
#endif
    return ht_roulette(nthr, judged_share, ht_sample(seed, pixel, sample, bounce, HT_DIM_RR));
}


/* One next-event estimate at shading point sp of a path with throughput thr, drawn with sample
 * index `sample`: a light picked (ht_nee_sample, from stratum `stratum` of `strata`), the BCSDF
 * evaluated towards it, MIS where BCSDF sampling can find that light too.  Fills the shadow ray
 * and its unoccluded contribution (and the light's direction, for --aovs, and the light sample's
 * weight before the BCSDF and MIS, for --indirect dual); returns 0 when there is no ray to trace.
 * With --light-vertices, p_cont >= 0 is the density with which the path's continuation found this
 * fibre (kernels/integrator/light_vertices.h): an estimate of a light that starts light vertices
 * then takes the continuation's balance weight against the connections to them (p_cont < 0: none). */
HT_FN int ht_next_event(__global const HtLight* lights, uint light_count, const HtEnvironment* env,
                        __global const float* env_texels, __global const float* env_marginal,
                        __global const float* env_conditional, uint nee_count, uint seed, uint pixel,
                        uint sample, uint bounce, uint stratum, uint strata, const HtShadingPoint* sp,
                        float3 thr, float share, const HtLightVertices* lv, float p_cont,
                        volatile __global uint* counters, HtRay* shadow_ray, float3* contrib, float3* wi,
                        float3* light_weight) {
    HtLightSample ls;
    float inv_pick;
    uint picked;
    if (!ht_nee_sample(lights, light_count, env, env_texels, env_marginal, env_conditional, nee_count, seed,
                       pixel, sample, bounce, stratum, strata, sp, &ls, &inv_pick, &picked))
        return 0;
    float3 value;
    float pdf_bsdf = 0.0f;
    /* lights that BCSDF sampling can also reach (the environment map) share the estimate by MIS;
     * the others keep weight 1 and need no BCSDF pdf */
    ht_point_eval(sp, ls.wi, &value, ls.pdf > 0.0f ? &pdf_bsdf : 0);
#ifdef HT_LIGHT_GUIDE
    /* a continuation finds the light with the guided mixture's density, not the BCSDF's */
    if (ls.pdf > 0.0f) pdf_bsdf = ht_guided_pdf(sp, lights, light_count, HT_LIGHT_GUIDE, bounce, ls.wi, pdf_bsdf);
#endif
    float w = ls.pdf > 0.0f ? ht_mis_power(ls.pdf / inv_pick, pdf_bsdf) : 1.0f;
#ifdef HT_LIGHT_VERTICES
    if (p_cont >= 0.0f && picked < light_count) {
        const HtLight light = lights[picked];
        w *= ht_light_vertex_mis_continuation(
            p_cont, ht_light_vertex_density(lv, &light, picked, light_count, sp->axis_point, sp->tangent));
    }
#endif
    float3 c = thr * value * ls.li_over_pdf * (inv_pick * w);
    if (!ht_finite3(c)) {
        atomic_inc(&counters[HT_COUNTER_NAN]);
        return 0;
    }
#ifdef HT_LIGHT_THRESHOLD
    /* From the second vertex on: the first vertex's direct light is what stratified numbers make
     * converge fastest, and there the roulette's noise cost more than its rays saved
     * (docs/PERFORMANCE.md §8).  The weight is for the whole camera sample, as roulette judges a
     * continuation (roulette.h); before --clamp-indirect, so that a survivor's T / q is capped too. */
    if (bounce > 0u) {
        const float q = ht_max_channel(thr * value) * (inv_pick * w) / share;
        /* the survival draw only where it decides something (a Sobol' draw is not free) */
        if (q < HT_LIGHT_THRESHOLD)
            c = ht_light_roulette(c, q, HT_LIGHT_THRESHOLD, ht_sample(seed, pixel, sample, bounce, HT_DIM_LIGHT_RR));
    }
#endif
    c = ht_clamp_indirect(c, bounce + 1u, share);
    if (!(c.x + c.y + c.z > 0.0f)) return 0;
    float3 o = ht_point_spawn(sp, ls.wi);
    shadow_ray->ox = o.x; shadow_ray->oy = o.y; shadow_ray->oz = o.z;
    shadow_ray->dx = ls.wi.x; shadow_ray->dy = ls.wi.y; shadow_ray->dz = ls.wi.z;
    shadow_ray->tmin = 0.0f;
    shadow_ray->tmax = ht_point_shadow_tmax(sp, ls.distance);
    *contrib = c;
    *wi = ls.wi;
    *light_weight = thr * ls.li_over_pdf * inv_pick;
    return shadow_ray->tmax > 0.0f;
}

#ifdef HT_LIGHT_VERTICES
/* --light-vertices: fibre vertex sp (a vertex of `bounce`, throughput thr, carrying `share` of its
 * camera sample) connects to one light vertex of its camera sample `sample`, picked uniformly
 * (kernels/integrator/light_vertices.h has the estimator and its weights).  Fills the connection's
 * shadow ray -- from where a ray towards y leaves x to where one leaving y towards x would start,
 * stopped short of y's fibre by its radius over the foreshortening -- and its unoccluded
 * contribution; returns 0 when there is none. */
HT_FN int ht_connect_light_vertex(HT_SEGS_PARAM, HT_POINTS_PARAM, __global const uint* strand_material,
                                  __global const HtMaterial* materials, __global const HtLight* lights,
                                  uint light_count, __global const HtHit* light_hits, const HtLightVertices* lv,
                                  uint seed, uint pixel, uint sample, uint vertex_sample, uint bounce,
                                  uint field_mode, float pixel_angle, float n_a, float share,
                                  const HtShadingPoint* sp, float3 thr, volatile __global uint* counters,
                                  HtRay* ray, float3* contrib) {
    const float u = ht_sample(seed, pixel, vertex_sample, bounce, HT_DIM_LV_PICK);
    const uint j = min((uint)(u * (float)lv->count), lv->count - 1u);
    const uint l = ht_light_vertex_light(j, light_count);
    const HtLight light = lights[l];
    if (light.type == HT_LIGHT_SPHERE) return 0; /* starts no light rays */
    const HtHit lh = light_hits[(sample - lv->first_sample) * lv->count + j];
    if (lh.segment == HT_NO_HIT) return 0;
    const HtSegment seg = HT_SEG(lh.segment);
#if HT_FEATURE_MESHES
    if (ht_seg_flags(seg) & HT_SEG_TRIANGLE) return 0;
#endif
    const HtPoint a = HT_POINT(seg.point), b = HT_POINT(seg.point + 1u);
    const float3 pa = (float3)(a.x, a.y, a.z), pb = (float3)(b.x, b.y, b.z);
    const float3 y = pa + (pb - pa) * lh.u, ty = (float3)(lh.tx, lh.ty, lh.tz);
    float3 d = y - sp->axis_point;
    float dd = dot(d, d);
    if (!(dd > 0.0f)) return 0;
    const float3 o = ht_point_spawn(sp, d * rsqrt(dd));
    d = y - o;
    dd = dot(d, d);
    if (!(dd > 0.0f)) return 0;
    const float r = sqrt(dd);
    const float3 w = d / r;
    const float cos_y = ht_fibre_facing(ty, w);
    const float reach = r - lh.radius * 1.01f / max(cos_y, 0.05f);
    if (!(reach > 0.0f)) return 0;
    float3 value_x;
    float pdf_x = 0.0f;
    ht_point_eval(sp, w, &value_x, &pdf_x);
#ifdef HT_LIGHT_GUIDE
    pdf_x = ht_guided_pdf(sp, lights, light_count, HT_LIGHT_GUIDE, bounce, w, pdf_x);
#endif
    if (!(value_x.x + value_x.y + value_x.z > 0.0f)) return 0;
    /* y as the ray from x would find it: from o along w, at the light ray's offset h */
    HtRay to_y = {o.x, o.y, o.z, 0.0f, w.x, w.y, w.z, r};
    HtHit at_y = lh;
    at_y.t = r;
    HtShadingPoint spy;
    ht_fibre_point(materials[strand_material[ht_seg_strand(seg)]], a, b, &to_y, &at_y, HT_PATH_FROM_FIBRE, bounce + 1u,
                   field_mode, pixel_angle, &spy);
    /* the light at y, as y's own estimate of this light would find it unshadowed */
    HtLightSample ls;
    if (!ht_sample_light(&light, y, 0.5f, 0.5f, &ls)) return 0;
    float3 value_y;
    ht_point_eval(&spy, ls.wi, &value_y, 0);
    const float p_light = ht_light_vertex_density(lv, &light, l, light_count, y, ty);
    const float p_cont = n_a * pdf_x * cos_y / dd;
    if (!(p_cont + p_light > 0.0f)) return 0;
    const float3 weight = thr * value_x * value_y * (cos_y / (dd * (p_cont + p_light)));
    float3 c = weight * ls.li_over_pdf;
    if (!ht_finite3(c)) {
        atomic_inc(&counters[HT_COUNTER_NAN]);
        return 0;
    }
#ifdef HT_LIGHT_THRESHOLD
    /* judged as a next-event estimate is (ht_next_event), by its weight without the light */
    {
        const float q = ht_max_channel(weight) / share;
        if (q < HT_LIGHT_THRESHOLD)
            c = ht_light_roulette(c, q, HT_LIGHT_THRESHOLD, ht_sample(seed, pixel, vertex_sample, bounce, HT_DIM_LV_RR));
    }
#endif
    c = ht_clamp_indirect(c, bounce + 2u, share);
    if (!(c.x + c.y + c.z > 0.0f)) return 0;
    ray->ox = o.x; ray->oy = o.y; ray->oz = o.z;
    ray->dx = w.x; ray->dy = w.y; ray->dz = w.z;
    ray->tmin = 0.0f;
    ray->tmax = reach;
    *contrib = c;
    return 1;
}
#endif

__kernel void shade(HT_SEGS_PARAM, HT_POINTS_PARAM, HT_TRIS_PARAM, HT_SCENE_PARAMS, HT_SHADE_QUEUE_PARAMS,
                    HtBounce b HT_SHADE_AOV_PARAMS HT_SHADE_DUAL_PARAMS HT_SHADE_LV_PARAMS) {
    const uint seed = b.seed, bounce = b.bounce, max_depth = b.max_depth;
    const uint field_mode = b.field_mode;
    const float pixel_angle = b.pixel_angle;
    const uint splits = b.splits, light_samples = b.light_samples;
    const float share = 1.0f / (float)splits; /* of its camera sample, in every continuation */
    /* the last vertex samples a BCSDF ray too when there is light it can find (the environment),
     * so that both halves of the vertex's MIS estimate are there */
    const uint ext_depth = env.enabled ? max_depth + 1u : max_depth;
    const int extend = bounce + 1u < ext_depth;
    /* the stage slots (continuations) and shadow slots (light samples) of each ray */
    const uint continuations = bounce == 0u && extend ? splits : 1u;
    const uint lights_here = bounce == 0u ? light_samples : 1u;
    uint k = get_global_id(0);
    int active = k < count;
    uint shadows = 0u;
    int cut = 0;

    if (active) {
        const uint p = ray_path[k];
        HtPathState st = paths[p];
        const uint sample = st.sample;
        HtRay ray = rays[k];
        HtHit hit = hits[k];
#if HT_FEATURE_AOVS
        __global float* rec = aovs + (size_t)p * HT_AOV_STRIDE;
        if (bounce == 0u) ht_aov_begin(rec, &hit, max(splits, light_samples));
        const float4 frac = ht_aov_fractions(rec);
#endif
        /* every stage slot of the ray says whether a path goes on from it: compact reads them all */
        for (uint j = 0u; j < continuations; ++j) stage_path[k * continuations + j] = HT_NO_PATH;
        /* a camera path's first vertex draws its own numbers, a continuation its own (kernels/rng.h) */
        const uint vertex_sample = bounce == 0u ? sample : ht_continuation_sample(sample, splits, st.split);
        float3 thr = ht_load3(st.throughput);
        float3 dir = (float3)(ray.dx, ray.dy, ray.dz);
        const uint nee_count = light_count + ht_env_in_nee(&env);
        const int scatters = hit.segment != HT_NO_HIT && bounce < max_depth;
        HtShadingPoint sp;
        uint fibre_material = HT_NO_PATH;
        if (hit.segment == HT_NO_HIT) {
            float3 le = ht_env_eval(&env, env_texels, dir);
            float w = 1.0f;
            if (!(st.flags & HT_PATH_FROM_CAMERA) && ht_env_in_nee(&env)) {
                float p_light = ht_env_pdf(&env, env_marginal, env_conditional, dir) / (float)nee_count;
                w = ht_mis_power(st.last_pdf, p_light);
            }
            float3 add = ht_clamp_indirect(thr * le * w, bounce, share);
            if (ht_finite3(add)) {
                st.radiance[0] += add.x; st.radiance[1] += add.y; st.radiance[2] += add.z;
#if HT_FEATURE_AOVS
                ht_aov_add_light(rec, add, bounce, frac);
#endif
            } else {
                atomic_inc(&counters[HT_COUNTER_NAN]);
            }
        } else if (!scatters) {
            cut = 1;
        } else {
            /* without an environment nothing is traced past the last vertex: a path counts as
             * cut when it scatters there -- except under --indirect dual, whose terms stand for
             * the light beyond it */
#if HT_FEATURE_INDIRECT_DUAL
            cut = 0;
#else
            cut = bounce + 1u == max_depth && !env.enabled;
#endif
            HtSegment seg = HT_SEG(hit.segment);
#if HT_FEATURE_MESHES
            if (ht_seg_flags(seg) & HT_SEG_TRIANGLE)
                ht_surface_point(HT_TRI_SHADING(ht_seg_strand(seg)), &ray, &hit, textures, texture_count, texels, &sp);
            else
#endif
            {
                fibre_material = strand_material[ht_seg_strand(seg)];
                ht_fibre_point(materials[fibre_material], HT_POINT(seg.point),
                               HT_POINT(seg.point + 1u), &ray, &hit, st.flags, bounce, field_mode,
                               pixel_angle, &sp);
            }
        }

        /* next-event estimation: one light sample, or at a camera path's first vertex M of them
         * (--first-hit-light-samples; each with 1/M of the weight, numbers of its own and its own
         * stratum of the light pick), sample j credited to path state p + j so that no two shadow
         * slots of a bounce add to one path.  Every shadow slot of the ray is written; an empty
         * one has tmax < 0. */
        const float light_weight = bounce == 0u ? 1.0f / (float)light_samples : 1.0f;
        /* --light-vertices: a fibre that a continuation from a fibre found shares its estimate of
         * the light vertices' light with the connection from that fibre (light_vertices.h) */
        float p_cont = -1.0f;
#ifdef HT_LIGHT_VERTICES
        if (scatters && !sp.is_surface && (st.flags & HT_PATH_FROM_FIBRE))
            p_cont = ht_continuation_density(bounce == 1u ? (float)splits : 1.0f, st.last_pdf,
                                             (float3)(ray.ox, ray.oy, ray.oz), sp.axis_point, sp.tangent);
#else
        const HtLightVertices lv = {{0.0f, 0.0f, 0.0f, 0.0f}, 0u, 0u, 0u, 0u};
#endif
        const HtRay no_shadow_ray = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, -1.0f};
        for (uint j = 0u; j < lights_here; ++j) {
            HtRay shadow_ray = no_shadow_ray;
            float3 contrib = (float3)(0.0f), wl = (float3)(0.0f), lw = (float3)(0.0f);
            int queued = 0;
            if (scatters && nee_count > 0u) {
                const uint nee_sample =
                    bounce == 0u ? ht_continuation_sample(sample, light_samples, j) : vertex_sample;
                queued = ht_next_event(lights, light_count, &env, env_texels, env_marginal, env_conditional,
                                       nee_count, seed, st.pixel, nee_sample, bounce, j, lights_here, &sp,
                                       thr * light_weight, share, &lv, p_cont, counters, &shadow_ray,
                                       &contrib, &wl, &lw);
            }
            if (!queued) shadow_ray = no_shadow_ray;
            const uint slot = k * lights_here + j;
            shadow_rays[slot] = shadow_ray;
            HtShadowContrib sc;
            sc.contrib[0] = contrib.x; sc.contrib[1] = contrib.y; sc.contrib[2] = contrib.z;
            sc.path = p + j;
            shadow_contrib[slot] = sc;
#if HT_FEATURE_INDIRECT_DUAL
            HtDualRecord dr = {{0.0f, 0.0f, 0.0f}, HT_NO_PATH, 0.0f, 0.0f, 0.0f, 0.0f};
            if (queued && !sp.is_surface) {
                const float3 wil = ht_to_fiber_local(wl, sp.fx, sp.fy, sp.fz);
                dr.weight[0] = lw.x; dr.weight[1] = lw.y; dr.weight[2] = lw.z;
                dr.material = fibre_material;
                dr.theta_i = asin(clamp(wil.x, -1.0f, 1.0f));
                dr.theta_o = asin(clamp(sp.wo_l.x, -1.0f, 1.0f));
                dr.phi = ht_relative_phi(sp.wo_l, wil);
            }
            dual_records[slot] = dr;
#endif
#if HT_FEATURE_AOVS
            const float4 f = !queued ? (float4)(0.0f)
                             : bounce == 0u ? ht_aov_lobe_fractions(&sp, wl)
                                            : frac;
            __global float* sa = shadow_aov + (size_t)slot * HT_SHADOW_AOV_STRIDE;
            sa[0] = f.x; sa[1] = f.y; sa[2] = f.z; sa[3] = f.w;
            sa[4] = bounce == 0u ? 1.0f : 0.0f;
#endif
            shadows += (uint)queued;
        }

#ifdef HT_LIGHT_VERTICES
        /* the connection to a light vertex, in slot k of its own queue (resolved after the
         * next-event estimates' slots, so that no two slots of one launch add to a path) */
        {
            HtRay connect_ray = no_shadow_ray;
            float3 cc = (float3)(0.0f);
            int connected = 0;
            if (scatters && !sp.is_surface && bounce + 1u < max_depth)
                connected = ht_connect_light_vertex(HT_SEGS_ARG, HT_POINTS_ARG, strand_material, materials, lights,
                                                    light_count, light_hits, &lv, seed, st.pixel, sample,
                                                    vertex_sample, bounce, field_mode, pixel_angle,
                                                    bounce == 0u ? (float)splits : 1.0f, bounce == 0u ? 1.0f : share,
                                                    &sp, thr, counters, &connect_ray, &cc);
            if (!connected) connect_ray = no_shadow_ray;
            connect_rays[k] = connect_ray;
            HtShadowContrib sc;
            sc.contrib[0] = cc.x; sc.contrib[1] = cc.y; sc.contrib[2] = cc.z;
            sc.path = p;
            connect_contrib[k] = sc;
            shadows += (uint)connected;
        }
#endif

        /* extension rays: continuation 0 goes on in the path's own state, continuations 1..
         * in copies that start without radiance (with --aovs, continuation 0's sample at the
         * camera vertex is also its albedo estimate) */
#if HT_FEATURE_AOVS
        const int want_sample = scatters && (extend || bounce == 0u);
#else
        const int want_sample = scatters && extend;
#endif
        /* the full mixture's density (not one lobe's) where a continuation has an MIS partner: an
         * environment map, or with --light-vertices the connection */
#ifdef HT_LIGHT_VERTICES
        const int mixture = 1;
#else
        const int mixture = (int)ht_env_in_nee(&env);
#endif
        for (uint j = 0u; want_sample && j < continuations; ++j) {
            HtPathState fork = st;
            HtPathState* cont = j == 0u ? &st : &fork;
            fork.radiance[0] = fork.radiance[1] = fork.radiance[2] = 0.0f;
            fork.split = j;
            /* the camera path's split takes 1/N of the weight, later vertices keep theirs */
            const float split_weight = bounce == 0u ? share : 1.0f;
            const uint cont_sample = ht_continuation_sample(sample, splits, cont->split);
            float3 wi, weight;
            float pdf;
#ifdef HT_LIGHT_GUIDE
            const int sampled = ht_point_sample_guided(&sp, lights, light_count, HT_LIGHT_GUIDE, seed, st.pixel,
                                                       cont_sample, bounce, mixture, &wi, &weight, &pdf);
#else
            const int sampled =
                ht_point_sample(&sp, seed, st.pixel, cont_sample, bounce, mixture, &wi, &weight, &pdf);
#endif
            if (extend && sampled) {
                float3 nthr =
                    ht_roulette_at(thr * weight * split_weight, share, seed, st.pixel, cont_sample, bounce, max_depth);
                HtRay next_ray;
                if (ht_continue_path(cont, nthr, pdf, ht_point_spawn(&sp, wi), wi, !sp.is_surface, &next_ray, counters)) {
                    stage_rays[k * continuations + j] = next_ray;
                    stage_path[k * continuations + j] = p + j;
                    if (j > 0u) paths[p + j] = fork;
                }
            }
#if HT_FEATURE_AOVS
            if (bounce == 0u && sampled && ht_finite3(weight)) {
                __global float* cont_rec = rec + (size_t)j * HT_AOV_STRIDE;
                if (j == 0u) ht_aov_add3(rec, HT_AOV_ALBEDO, weight);
                const float4 f = ht_aov_lobe_fractions(&sp, wi);
                cont_rec[HT_AOV_FRACTIONS] = f.x; cont_rec[HT_AOV_FRACTIONS + 1u] = f.y;
                cont_rec[HT_AOV_FRACTIONS + 2u] = f.z; cont_rec[HT_AOV_FRACTIONS + 3u] = f.w;
            }
#endif
        }
        paths[p] = st;
    }

    /* statistics only: the shadow queue is not compacted, its count is reported.  One aggregated
     * append per kernel (kernels/queue.h says why); cut paths are few and take a plain atomic. */
    __local uint lcount, lbase;
    ht_queue_append(shadows, &lcount, &lbase, &counters[HT_COUNTER_SHADOW]);
    if (cut) atomic_inc(&counters[HT_COUNTER_CUT]);
}
