/* Every switch and value the kernels are compiled with, declared once: its name, its default
 * and what it means.  The host emits them (host/render/features.cpp walks HT_FEATURE_SWITCHES
 * for the -D options and the --verbose lines) and tests/unit/kernel_features_test.cpp fails when
 * an emitted define is read by no kernel.
 *
 * Feature switches, 0 or 1: what a scene lacks is compiled out of the render program, which
 * keeps its build time and register pressure down.  Undefined means 1, so the host tests, the
 * fibre CLI and tools that build without options see everything. */
#ifndef HT_FEATURES_H
#define HT_FEATURES_H

#define HT_FEATURE_SWITCHES(X)                                                                     \
    X(LIGHT_SPOT, "spot lights")                                                                   \
    X(LIGHT_DIRECTIONAL, "directional lights")                                                     \
    X(LIGHT_SPHERE, "sphere lights")                                                               \
    X(MODEL_KAJIYA, "model kajiya")                                                                \
    X(MODEL_MARSCHNER, "model marschner")                                                          \
    X(MODEL_ZINKE, "model zinke")                                                                  \
    X(MODEL_CHIANG, "model chiang")                                                                \
    X(INDIRECT_AFS, "translucent AFS shadow rays (--indirect afs)")                                \
    X(INDIRECT_DUAL, "dual scattering (--indirect dual)")                                          \
    X(MESHES, "triangle meshes")                                                                   \
    X(TEXTURES, "base colour textures")                                                            \
    X(LOBE_TT, "lobe TT")                                                                          \
    X(LOBE_TRT, "lobe TRT (chiang: + TRRT+)")                                                      \
    X(AOVS, "arbitrary output values (render --aovs)")                                            \
    X(PATH_GRID, "path rays from a uniform grid (--path-rays)")

/* Point lights need no switch: their code is the part every positional light shares. */
#ifndef HT_FEATURE_LIGHT_SPOT
#define HT_FEATURE_LIGHT_SPOT 1
#endif
#ifndef HT_FEATURE_LIGHT_DIRECTIONAL
#define HT_FEATURE_LIGHT_DIRECTIONAL 1
#endif
#ifndef HT_FEATURE_LIGHT_SPHERE
#define HT_FEATURE_LIGHT_SPHERE 1
#endif
#ifndef HT_FEATURE_MODEL_KAJIYA
#define HT_FEATURE_MODEL_KAJIYA 1
#endif
#ifndef HT_FEATURE_MODEL_MARSCHNER
#define HT_FEATURE_MODEL_MARSCHNER 1
#endif
#ifndef HT_FEATURE_MODEL_ZINKE
#define HT_FEATURE_MODEL_ZINKE 1
#endif
#ifndef HT_FEATURE_MODEL_CHIANG
#define HT_FEATURE_MODEL_CHIANG 1
#endif
/* the AFS stage is a separate kernel: only the render program includes it, when asked */
#ifndef HT_FEATURE_INDIRECT_AFS
#define HT_FEATURE_INDIRECT_AFS 0
#endif
/* --indirect dual: shade's records and the dual shadow stage (a setting, off unless asked) */
#ifndef HT_FEATURE_INDIRECT_DUAL
#define HT_FEATURE_INDIRECT_DUAL 0
#endif
/* hair-only scenes get 0: the leaf loop and shade stay pure hair */
#ifndef HT_FEATURE_MESHES
#define HT_FEATURE_MESHES 1
#endif
#ifndef HT_FEATURE_TEXTURES
#define HT_FEATURE_TEXTURES 1
#endif
/* lobes whose energy bound stays under 1e-3 of R's for every material (kernels/fiber/lobes.h) */
#ifndef HT_FEATURE_LOBE_TT
#define HT_FEATURE_LOBE_TT 1
#endif
#ifndef HT_FEATURE_LOBE_TRT
#define HT_FEATURE_LOBE_TRT 1
#endif

/* per-path output records (kernels/aovs.h): a setting, not a scene feature, so off unless asked */
#ifndef HT_FEATURE_AOVS
#define HT_FEATURE_AOVS 0
#endif

/* path rays' closest hits from a uniform grid of capsule lists (kernels/geometry/path_grid.h): a
 * setting, off unless the render chose it */
#ifndef HT_FEATURE_PATH_GRID
#define HT_FEATURE_PATH_GRID 0
#endif

/* Values (defaults where they are read):
 *   HT_GEOMETRY_PAGES K, HT_GEOMETRY_PAGE_LOG2 S   geometry split over K buffers of 2^S records
 *                                                  (kernels/geometry/pages.h; default 1: one)
 *   HT_CLAMP_INDIRECT C          --clamp-indirect cap (undefined: off; kernels/stages/shade.cl)
 *   HT_LIGHT_THRESHOLD T         --light-threshold (undefined: off; kernels/integrator/roulette.h,
 *                                read in kernels/stages/shade.cl)
 *   HT_LIGHT_PICK_IMPORTANCE     --light-pick importance with 2..HT_LIGHT_PICK_MAX lights
 *                                (undefined: uniform; kernels/lights.h, kernels/stages/shade.cl)
 *   HT_LIGHT_GUIDE F             --light-guiding share (undefined: off, as for a scene without
 *                                lights; kernels/integrator/light_guide.h, kernels/stages/shade.cl)
 *   HT_REGULARIZE_WIDTH W        --regularize width in radians (undefined: off;
 *                                kernels/integrator/shading_point.h)
 *   HT_SPAWN_PBRT                --spawn-offset pbrt (undefined: capsule offsets; same file)
 *   HT_SAMPLER_SOBOL             --sampler: 1 Owen-scrambled Sobol', 0 independent (default 0 for
 *                                builds without options; kernels/rng.h)
 *   HT_RR_START_BOUNCE B         first bounce with Russian roulette (4; kernels/stages/shade.cl) */

#endif
