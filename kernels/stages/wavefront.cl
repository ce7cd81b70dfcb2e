/* The render program: every stage kernel of the wavefront path tracer, built once per
 * combination of scene features (-D options chosen by host/render/features.cpp). */
#include "generate_camera_rays.cl"
#include "intersect_closest.cl"
#include "shade.cl"
#include "intersect_shadow.cl"
#include "resolve_shadows.cl"
#if HT_FEATURE_INDIRECT_AFS
#include "intersect_shadow_afs.cl"
#endif
#include "compact.cl"
#include "accumulate.cl"
