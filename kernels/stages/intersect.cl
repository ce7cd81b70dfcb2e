/* Program used by DeviceTracer (`hairtrace bench`): the intersection stages in one build. */
#include "intersect_closest.cl"
#include "intersect_shadow.cl"
/* the render's path-ray stage, built with HT_FEATURE_PATH_GRID (DeviceTracer): its grid walk */
#include "intersect_closest_paths.cl"
/* the render's shadow stage with the lights' per-cell lists (DeviceTracer::use_shadow_lists) */
#include "intersect_shadow_lists.cl"
/* the render's camera stage with per-pixel lists (DeviceTracer::set_camera_lists) */
#include "intersect_camera.cl"
