/* Program used by DeviceTracer (`hairtrace bench`): the intersection stages in one build. */
#include "intersect_closest.cl"
#include "intersect_shadow.cl"
/* the render's path-ray stage, built with HT_FEATURE_PATH_GRID (DeviceTracer): its grid walk */
#include "intersect_closest_paths.cl"
