/* A path vertex behind the one interface that next-event estimation and the path's continuation
 * use (kernels/stages/shade.cl), so that both are written once for every kind of surface:
 *   eval(wi)         scattering value for light arriving from wi (cosine included) and, unless
 *                    the pdf pointer is 0, the pdf with which sample() would have chosen wi (MIS);
 *   sample(u)        a continuation direction, its weight value * cos / pdf, and the pdf;
 *   spawn(w)         where a ray leaving the vertex in direction w starts;
 *   shadow_tmax(d)   how far a shadow ray towards a light d away may look for occluders.
 * Two kinds: a hair fibre (its BCSDF in the fibre frame at the hit's offset h) and, with
 * HT_FEATURE_MESHES, a Lambertian triangle (kernels/surface/lambert.h). */
#ifndef HT_INTEGRATOR_SHADING_POINT_H
#define HT_INTEGRATOR_SHADING_POINT_H

#include "../types.h"
#include "../rng.h"
#include "../geometry/fiber_frame.h"
#include "../fiber/bcsdf.h"
#if HT_FEATURE_MESHES
#include "../surface/lambert.h"
#if HT_FEATURE_TEXTURES
#include "../surface/texture.h"
#endif
#endif

typedef struct {
    int is_surface;
    real3 p; /* the hit point (light sampling starts here) */
    /* fibre: material (with --fiber-field and --regularize applied), frame, offset h */
    HtMaterial mat;
    HtBcsdfWo wo_prep; /* what the fibre model derives from wo_l and h, for every eval and sample here */
    real3 fx, fy, fz, wo_l, axis_point, tangent;
    real h, radius;
    /* surface: geometric and shading normals facing the viewer, albedo, hit distance */
    real3 ng, ns, albedo;
    real t;
} HtShadingPoint;

/* --regularize B (path regularisation, Kaplanyan & Dachsbacher 2013; Cycles' "filter glossy"):
 * at hair hit by a path that has already scattered, the Marschner-family lobes are widened to at
 * least HT_REGULARIZE_WIDTH radians (longitudinal betas; zinke's azimuthal sigma).  Light reaching
 * the camera through two narrow lobes is then no longer a rare, bright sample; the lobes keep
 * their energy (normalised Gaussians), so the bias is a blur of indirect highlights, measured in
 * docs/PERFORMANCE.md.  Undefined: compiled out. */
HT_FN void ht_regularize(HtMaterial* m, uint bounce) {
#ifdef HT_REGULARIZE_WIDTH
    if (bounce > 0u && (m->model == HT_MODEL_MARSCHNER || m->model == HT_MODEL_ZINKE)) {
        m->beta_r = ht_max(m->beta_r, HT_REGULARIZE_WIDTH);
        m->beta_tt = ht_max(m->beta_tt, HT_REGULARIZE_WIDTH);
        m->beta_trt = ht_max(m->beta_trt, HT_REGULARIZE_WIDTH);
        m->azim_sigma = ht_max(m->azim_sigma, HT_REGULARIZE_WIDTH);
#if HT_FEATURE_MODEL_MARSCHNER || HT_FEATURE_MODEL_ZINKE
        ht_mz_prepare_material(m); /* the sampling proxy's constants follow the wider betas */
#endif
    }
#endif
}

/* A fibre hit: material a..b's strand uses, hit by `ray`. */
HT_FN void ht_fibre_point(HtMaterial mat, HtPoint a, HtPoint b, const HtRay* ray, const HtHit* hit,
                          uint path_flags, uint bounce, uint field_mode, real pixel_angle,
                          HtShadingPoint* sp) {
    if (field_mode != HT_FIELD_MATERIAL &&
        (mat.model == HT_MODEL_MARSCHNER || mat.model == HT_MODEL_ZINKE)) {
        /* auto: the near-field model where a fibre covers a good part of the pixel footprint
         * (close-ups) and for hair-to-hair light (neighbours are close); the far-field model
         * where many fibres share a camera pixel */
        int near_field = field_mode == HT_FIELD_NEAR ||
                         (field_mode == HT_FIELD_AUTO &&
                          (!(path_flags & HT_PATH_FROM_CAMERA) ||
                           HT_R(2) * hit->radius >= HT_FIELD_AUTO_COVERAGE * hit->t * pixel_angle));
        mat.model = near_field ? HT_MODEL_ZINKE : HT_MODEL_MARSCHNER;
    }
    ht_regularize(&mat, bounce);
    sp->is_surface = 0;
    sp->mat = mat;
    real3 pa = make_real3(a.x, a.y, a.z), pb = make_real3(b.x, b.y, b.z);
    sp->axis_point = pa + (pb - pa) * hit->u;
    sp->tangent = make_real3(hit->tx, hit->ty, hit->tz);
    real3 dir = make_real3(ray->dx, ray->dy, ray->dz);
    real3 wo = -dir;
    ht_fiber_frame(sp->tangent, wo, &sp->fx, &sp->fy, &sp->fz);
    sp->wo_l = ht_to_fiber_local(wo, sp->fx, sp->fy, sp->fz);
    sp->h = hit->h;
    sp->radius = hit->radius;
    ht_bcsdf_prepare(&sp->mat, sp->wo_l, sp->h, &sp->wo_prep);
    sp->p = make_real3(ray->ox, ray->oy, ray->oz) + dir * hit->t;
}

#if HT_FEATURE_MESHES
/* A triangle hit: ts is its shading record; the albedo is baseColorFactor times the base colour
 * texture at the interpolated TEXCOORD_0 when there is one (HT_FEATURE_TEXTURES). */
HT_FN void ht_surface_point(HtTriangleShading ts, const HtRay* ray, const HtHit* hit,
                            HT_CONST_GLOBAL HtTexture* textures, uint texture_count,
                            HT_CONST_GLOBAL uint* texels, HtShadingPoint* sp) {
    real3 dir = make_real3(ray->dx, ray->dy, ray->dz);
    sp->is_surface = 1;
    sp->p = make_real3(ray->ox, ray->oy, ray->oz) + dir * hit->t;
    sp->t = hit->t;
    real3 ng = make_real3(hit->tx, hit->ty, hit->tz);
    real b0 = HT_R(1) - hit->u - hit->h;
    real3 ns = ts.n0[3] > 0.0f ? make_real3(ts.n0[0], ts.n0[1], ts.n0[2]) * b0 +
                                     make_real3(ts.n1[0], ts.n1[1], ts.n1[2]) * hit->u +
                                     make_real3(ts.n2[0], ts.n2[1], ts.n2[2]) * hit->h
                               : ng;
    ht_lambert_face_forward(-dir, &ng, &ns);
    sp->ng = ng;
    sp->ns = ns;
    sp->albedo = make_real3(ts.albedo[0], ts.albedo[1], ts.albedo[2]);
#if HT_FEATURE_TEXTURES
    if (ts.texture < texture_count) {
        real tu = ts.uv[0] * b0 + ts.uv[2] * hit->u + ts.uv[4] * hit->h;
        real tv = ts.uv[1] * b0 + ts.uv[3] * hit->u + ts.uv[5] * hit->h;
        sp->albedo = sp->albedo * ht_texture_sample(textures[ts.texture], texels, tu, tv);
    }
#endif
}

/* Offset of ray origins off a surface: the hit point carries rounding of a few ulps of its
 * coordinates and of the ray's t, so the offset scales with both; 1e-5 relative is ~80 float
 * ulps, far below any modelled detail (a fibre radius is >= 1e-4 of the scene in practice). */
HT_FN real3 ht_surface_spawn(real3 p, real t, real3 ng, real3 w) {
    real scale = ht_max(ht_max(fabs(p.x), fabs(p.y)), ht_max(fabs(p.z), t));
    real eps = HT_R(1e-5) * scale + HT_R(1e-7);
    return p + ng * (dot(ng, w) > HT_R(0) ? eps : -eps);
}
#endif

/* Origin for a ray leaving the fibre in direction w: the surface point on w's side of the axis,
 * a hair outside the fibre, so neither this capsule nor (for gentle bends) its neighbours are
 * re-hit from the inside.  The BCSDF already accounts for the light's path through the fibre. */
HT_FN real3 ht_fibre_spawn(real3 axis_point, real3 t, real3 fallback_side, real radius, real3 w) {
    real3 side = w - t * dot(w, t);
    real len2 = dot(side, side);
    side = len2 > HT_R(1e-12) ? side * rsqrt(len2) : fallback_side;
#ifdef HT_SPAWN_PBRT
    /* --spawn-offset pbrt, a diagnostic: pbrt-v4 offsets a curve's secondary rays from the hit
     * (on the axis plane of its ray-facing ribbon) along the normal by width * |n|_1, 1 to 1.73
     * fibre diameters, so they can skip the nearest neighbours (docs/ESTIMATOR.md measures it) */
    return axis_point + side * (HT_R(2) * radius * (fabs(side.x) + fabs(side.y) + fabs(side.z)));
#else
    return axis_point + side * (radius * HT_R(1.01));
#endif
}

HT_FN real3 ht_point_spawn(const HtShadingPoint* sp, real3 w) {
#if HT_FEATURE_MESHES
    if (sp->is_surface) return ht_surface_spawn(sp->p, sp->t, sp->ng, w);
#endif
    return ht_fibre_spawn(sp->axis_point, sp->tangent, sp->fz, sp->radius, w);
}

/* Shadow rays stop short of the light: of a sphere light's own surface (surfaces), and by the
 * origin's offset from the axis (fibres), so a light inside the offset is not occluded by it. */
HT_FN real ht_point_shadow_tmax(const HtShadingPoint* sp, real distance) {
#if HT_FEATURE_MESHES
    if (sp->is_surface) return ht_min(distance * HT_R(0.9999), HT_R(1e30));
#endif
    return ht_min(distance - sp->radius * HT_R(1.01), HT_R(1e30));
}

HT_FN void ht_point_eval(const HtShadingPoint* sp, real3 wi, real3* value, real* pdf) {
#if HT_FEATURE_MESHES
    if (sp->is_surface) {
        *value = sp->albedo * ht_lambert_eval(sp->ns, sp->ng, wi, pdf);
        return;
    }
#endif
    *value = make_real3(0, 0, 0);
    ht_bcsdf_eval_o(&sp->mat, &sp->wo_prep, sp->wo_l, ht_to_fiber_local(wi, sp->fx, sp->fy, sp->fz), sp->h, value,
                    pdf);
}

/* A fibre's continuation from the four uniforms u0..u3 (kernels/fiber/bcsdf.h's sampler); mixture
 * as ht_point_sample's. */
HT_FN int ht_point_sample_fibre(const HtShadingPoint* sp, real u0, real u1, real u2, real u3, int mixture,
                                real3* wi, real3* weight, real* pdf) {
    real3 wi_l = make_real3(0, 0, 0);
    *weight = make_real3(0, 0, 0);
    if (!ht_bcsdf_sample_mode_o(&sp->mat, &sp->wo_prep, sp->wo_l, sp->h, u0, u1, u2, u3, mixture, &wi_l, weight, pdf))
        return 0;
    *wi = sp->fx * wi_l.x + sp->fy * wi_l.y + sp->fz * wi_l.z;
    return 1;
}

/* Draws the vertex's uniforms from the BSDF slots of `bounce` (kernels/rng.h's layout).  mixture
 * 0 when no light can be met by the sampled ray (no MIS): *pdf may then be 0 and the weight that
 * of the drawn lobe alone (kernels/fiber/bcsdf.h, ht_bcsdf_sample_mode_o). */
HT_FN int ht_point_sample(const HtShadingPoint* sp, uint seed, uint pixel, uint sample, uint bounce, int mixture,
                          real3* wi, real3* weight, real* pdf) {
    /* the jointly stratified pair: a surface's cosine-weighted direction, a fibre's longitudinal angle */
    real u1, u2;
    ht_sample2(seed, pixel, sample, bounce, HT_DIM_BSDF_0 + 1u, HT_DIM_BSDF_0 + 2u, &u1, &u2);
#if HT_FEATURE_MESHES
    if (sp->is_surface) {
        /* cosine-weighted: value * cos / pdf is the albedo */
        *weight = sp->albedo;
        return ht_lambert_sample(sp->ns, sp->ng, u1, u2, wi, pdf);
    }
#endif
    real u0, u3;
    ht_sample2(seed, pixel, sample, bounce, HT_DIM_BSDF_0, HT_DIM_BSDF_0 + 3u, &u0, &u3);
    return ht_point_sample_fibre(sp, u0, u1, u2, u3, mixture, wi, weight, pdf);
}

#endif
