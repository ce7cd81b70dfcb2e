/* Argument bundles of the stage kernels, declared once.  OpenCL C 1.2 allows no pointers in
 * kernel-argument structs, so a bundle is a parameter list; the host sets each bundle with one
 * call (host/render/stage_args.h; the path grid's: host/bvh/path_grid_buffers.h), and
 * tests/render/stage_args_test.cpp checks that the host's argument names and order equal these
 * (CL_KERNEL_ARG_NAME).  Stage signatures read (geometry, scene, queue, per-launch values). */
#ifndef HT_STAGE_ARGS_H
#define HT_STAGE_ARGS_H

#include "../types.h"

/* What the scene gives shading besides its geometry: textures, materials, lights, environment. */
#define HT_SCENE_PARAMS                                                                            \
    __global const HtTexture *textures, uint texture_count, __global const uint *texels,           \
        __global const uint *strand_material, __global const HtMaterial *materials,                \
        __global const HtLight *lights, uint light_count, HtEnvironment env,                       \
        __global const float *env_texels, __global const float *env_marginal,                      \
        __global const float *env_conditional

/* shade's queues: the rays of this bounce with their hits and paths in, the shadow and
 * (uncompacted) extension queues and the counters out. */
#define HT_SHADE_QUEUE_PARAMS                                                                      \
    __global const HtRay *rays, __global const HtHit *hits, __global const uint *ray_path,         \
        uint count, __global HtPathState *paths, __global HtRay *shadow_rays,                      \
        __global HtShadowContrib *shadow_contrib, __global HtRay *stage_rays,                      \
        __global uint *stage_path, volatile __global uint *counters

/* render --aovs (kernels/aovs.h): the per-path records and, for the stages that resolve shadow
 * rays, the per-slot records of their contributions; the film's AOV sums for accumulate. */
#if HT_FEATURE_AOVS
#define HT_SHADE_AOV_PARAMS , __global float *aovs, __global float *shadow_aov
#define HT_RESOLVE_AOV_PARAMS , __global float *aovs, __global const float *shadow_aov
#define HT_ACCUMULATE_AOV_PARAMS , __global const float *aovs, __global float *film_aov
#else
#define HT_SHADE_AOV_PARAMS
#define HT_RESOLVE_AOV_PARAMS
#define HT_ACCUMULATE_AOV_PARAMS
#endif

/* --indirect dual (kernels/fiber/dual.h): shade's per-shadow-slot records for the dual stage */
#if HT_FEATURE_INDIRECT_DUAL
#define HT_SHADE_DUAL_PARAMS , __global HtDualRecord *dual_records
#else
#define HT_SHADE_DUAL_PARAMS
#endif

/* The path rays' grid (kernels/geometry/path_grid.h), after their own arguments, for the stages that
 * walk it with HT_FEATURE_PATH_GRID: intersect_closest_paths.cl and intersect_shadow.cl. */
#define HT_PATH_GRID_PARAMS __global const uint *grid_cells, __global const uint *grid_entries, HtPathGrid grid

/* --light-vertices (kernels/integrator/light_vertices.h): the pass's light rays and their hits in,
 * shade's connection per ray (shadow ray and contribution) out */
#ifdef HT_LIGHT_VERTICES
#define HT_SHADE_LV_PARAMS                                                                         \
    , __global const HtRay *light_rays, __global const HtHit *light_hits, HtLightVertices lv,      \
        __global HtRay *connect_rays, __global HtShadowContrib *connect_contrib
#else
#define HT_SHADE_LV_PARAMS
#endif

#endif /* HT_STAGE_ARGS_H */
