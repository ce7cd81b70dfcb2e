// Which pixels can see geometry at all: the camera rays of the others miss every primitive, so
// their value is the background's, the same in every sample, and the render need not trace them
// (Renderer, "pixels that see no geometry"; docs/PERFORMANCE.md section 8).
#pragma once

#include "render/candidate_lists.h"
#include "render/primitive_images.h"

#include <cstdint>
#include <vector>

namespace ht {

// Pixel indices (y * width + x), ascending: `seen` may meet geometry, `empty` cannot.
struct PixelFootprint {
    std::vector<uint32_t> seen, empty;
};

// A pixel is empty when the square its camera rays pass through (kernels/camera.h: jitter in
// [0, 1)^2 of the pixel, a pinhole) overlaps the projected bounds of no primitive: a capsule or a
// triangle lies in the convex hull of balls around its vertices (radius: the largest of the
// vertex's and its neighbours' radii, the hit radius being the mean of two), and the image of that
// hull is bounded by the hull of the balls' images.  Conservative by construction: the bounds are
// widened by kFootprintMarginPixels on every side, which covers the float rounding of ray
// directions and hits by orders of magnitude, and a primitive that reaches the eye's plane makes
// every pixel seen.  A camera whose frame cannot be inverted, or a non-finite point, sees
// everything.
PixelFootprint pixel_footprint(const ProjectedPrimitives& projected);
PixelFootprint pixel_footprint(const HtCamera& camera, const SceneGeometry& geometry);
// The same from the camera's candidate lists (enabled): a pixel whose list is empty sees nothing,
// as its list holds every primitive its rays can meet.  Tighter than the projection's 1-pixel
// margin, and made without a pass over the primitives.
PixelFootprint pixel_footprint(const PixelCandidates& lists);

}  // namespace ht
