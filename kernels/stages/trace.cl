/* The render program's stages around shade (stages/shade.cl, built as a program of its own):
 * camera rays (and --light-vertices' light rays), traversal, shadow resolution, compaction and
 * accumulation (and the --first-hit-splits auto pilot's accumulation).  They read few of the
 * scene features, so one build of them serves most scenes (host/render/renderer.cpp); the
 * translucent shadow stage of --indirect afs, which needs the fibre's lobes, is a program of its
 * own (stages/intersect_shadow_afs.cl), and so are the stages that read the camera's and the
 * shadow rays' candidate lists (stages/lists.cl). */
#include "generate_camera_rays.cl"
#include "intersect_closest_paths.cl"
#include "intersect_shadow.cl"
#include "resolve_shadows.cl"
#include "compact.cl"
#include "accumulate.cl"
#include "split_pilot.cl"
/* Only where they run: PoCL compiles every kernel of a program whose binary is read (which the
 * binary cache does), and each traversal kernel costs about 0.8 s of a cold build
 * (docs/PERFORMANCE.md section 2). */
#ifdef HT_LIGHT_VERTICES
#include "generate_light_rays.cl"
#include "intersect_closest.cl"
#endif
