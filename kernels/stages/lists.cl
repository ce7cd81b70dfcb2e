/* The stages that read the camera's per-pixel and the shadow rays' per-cell candidate lists
 * (host/render/candidate_lists.h, host/render/shadow_lists.h), a program of their own beside
 * trace.cl: built only for a render that makes lists (host/render/renderer.cpp), since PoCL compiles
 * every kernel of a cached program and each of these costs about 0.8 s of a cold build
 * (docs/PERFORMANCE.md section 2). */
#include "intersect_camera.cl"
#include "intersect_shadow_lists.cl"
