/* Program used by DeviceTracer (`hairtrace bench`): the intersection stages in one build (the list
 * stages, lists.cl, are a program of their own, built when a caller gives lists). */
#include "intersect_closest.cl"
/* both shadow kernels: the render's (by the grid with HT_FEATURE_PATH_GRID) and the tree's */
#define HT_SHADOW_TREE_TOO
#include "intersect_shadow.cl"
/* the render's path-ray stage, built with HT_FEATURE_PATH_GRID (DeviceTracer): its grid walk */
#include "intersect_closest_paths.cl"
