// What the render would know about a set of rays that a ray file does not say: the lights shadow
// rays run to and the camera that rays from one point come from, so that `hairtrace bench` can
// answer them with the render's own lists (render/shadow_lists.h, render/candidate_lists.h).
#pragma once

#include "kernels/types.h"

#include <cstdint>
#include <vector>

namespace ht {

// The lights a set of shadow rays runs to, as the render's shadow lists would have them: a
// direction that at least 1 % of the rays (and two) share bit for bit is a directional light's (a
// render's `--dump-rays`: the shade stage copies the light's direction); among the other rays that
// end, the point nearest the lines of the first and of the first across it is a point light's when
// more than half of them point at it and pass within 1e-4 of their distance to it (at least 1e-4):
// the anchor's shadow set, and bench's generated one.  At most kMaxShadowGrids, directional ones
// first, the most shared first.
std::vector<HtLight> lights_the_rays_run_to(const std::vector<HtRay>& rays);

// Rays that all leave one point, as a camera's do (the anchor's primary set): a camera there whose
// image holds every ray (its axis their mean direction, a square image of one pixel per ray, 16 to
// 4,096 a side), and each ray's pixel, so that the render's camera stage can trace them from the
// per-pixel lists that camera's render would make.  ok is false for fewer than 64 rays, rays from
// several points, or rays spread past 63 degrees from their mean.
struct FittedCamera {
    HtCamera camera{};
    std::vector<uint32_t> pixels;
    bool ok = false;
};
FittedCamera camera_of_the_rays(const std::vector<HtRay>& rays);

}  // namespace ht
