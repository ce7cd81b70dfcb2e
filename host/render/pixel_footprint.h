// Which pixels can see geometry at all: the camera rays of the others miss every primitive, so
// their value is the background's, the same in every sample, and the render need not trace them
// (Renderer, "pixels that see no geometry"; docs/PERFORMANCE.md section 8).
#pragma once

#include "bvh/bvh.h"
#include "kernels/types.h"

#include <cstdint>
#include <thread>
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
constexpr double kFootprintMarginPixels = 1.0;

// One primitive's image: bounds of where camera rays may meet it, in pixel coordinates (pixel
// (px, py) spans [px, px + 1) x [py, py + 1)), and its nearest depth (the frame coordinate along
// the camera's forward axis, kernels/camera.h).
struct PrimitiveImage {
    uint32_t primitive;  // index into SceneGeometry::segments (the leaf order)
    float depth;         // rounded down
    // A capsule's ends' bounds (x0, x1, y0, y1) in pixel units (x right, y down), not widened,
    // rounded outwards; a triangle's: both its box.
    float a[4], b[4];
    void box(double* x0_x1_y0_y1) const;  // the union of a and b
    // The pixels x_first .. x_last of row y that the hull of a and b, widened by `margin`, meets;
    // false for none.
    bool row_span(int y, double margin, int w, int* x_first, int* x_last) const;
};

// Every primitive's image, in point order, or bounded = false when nothing can be proved (see
// above).  depth_row: a camera ray's depth per unit of t is depth_row . d.
struct ProjectedPrimitives {
    int width = 0, height = 0;
    bool bounded = false;
    std::vector<PrimitiveImage> images;
    double depth_row[3] = {0, 0, 0};
};
ProjectedPrimitives project_primitives(const HtCamera& camera, const SceneGeometry& geometry);

// Shared with the light's grids (render/shadow_lists.h):
// the primitive beginning at each point (kNoPrimitive: none) and its vertex count (2 or 3),
// gathered once from the leaf order so the passes over primitives can run in point order;
constexpr uint32_t kNoPrimitive = 0xFFFFFFFFu;
struct PrimitiveStarts {
    std::vector<uint32_t> primitive;
    std::vector<uint8_t> vertices;
};
PrimitiveStarts primitive_starts(const SceneGeometry& geometry);
// the radius of the ball around point i that covers every primitive's surface there: the largest
// of its own and its neighbours' (a capsule's hit radius is the mean of its two ends');
double ball_radius(const SceneGeometry& geometry, size_t i);
// double -> float rounded down / up;
float round_down(double x);
float round_up(double x);
// the host's threads for these loops (at most 8), and body(thread, begin, end) over their
// contiguous shares of [0, n) in parallel.
int host_threads();
template <typename Body>
void in_parallel(size_t n, const Body& body) {
    const int threads = host_threads();
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] { body(t, n * size_t(t) / size_t(threads), n * size_t(t + 1) / size_t(threads)); });
    for (std::thread& th : pool) th.join();
}

PixelFootprint pixel_footprint(const ProjectedPrimitives& projected);
PixelFootprint pixel_footprint(const HtCamera& camera, const SceneGeometry& geometry);

// For each pixel, the primitives whose image covers it, nearest depth first: the only ones its
// camera rays can hit, so the closest hit among them is the tree's (kernels/stages/intersect_camera.cl).
// Pixel p's list is entries start[p] .. start[p] + count[p] of primitive / depth; a pixel with
// more than max_per_pixel keeps the tree (count[p] = kCandidatesUseTree).
// enabled = false (every pixel traverses the tree) when the projection is unbounded or the lists
// do not fit the budget with a cap of at least 8.
constexpr uint32_t kCandidatesUseTree = 0xFFFFFFFFu;  // kernels/stages/intersect_camera.cl's HT_CANDIDATES_USE_TREE
// The cap on a pixel's list (measured on pbrt's lock, docs/PERFORMANCE.md section 8: its densest
// pixels hold ~900 and still beat the tree) and the lists' budget, 8 bytes an entry: beyond it
// the cap halves until they fit, and below 8 no lists are made.
constexpr uint32_t kMaxCandidatesPerPixel = 1024;
constexpr uint64_t kMaxCandidateEntries = uint64_t(1) << 24;
// The lists' margin: the bounds are exact but for double rounding; what they must cover is the
// float arithmetic of the kernels' camera rays and capsule roots, relative errors of ~1e-7 of the
// distance, i.e. ~1e-7 radians, against 1/64 of a pixel's angle (3e-5 radians at 256 pixels
// over a 30-degree field, 5e-7 at 16,384).  A wider margin only lengthens the lists: thin
// fibres' entries stay near their true footprints.
constexpr double kCandidateMarginPixels = 1.0 / 64;
struct PixelCandidates {
    bool enabled = false;
    std::vector<uint32_t> start, count;  // per pixel
    std::vector<uint32_t> primitive;  // leaf index
    std::vector<float> depth;         // nearest depth, rounded down
    float depth_row[3] = {0, 0, 0};
    size_t tree_pixels = 0;
    uint32_t max_per_pixel = 0;  // the cap that fit the budget
};
PixelCandidates pixel_candidates(const ProjectedPrimitives& projected, uint32_t max_per_pixel = kMaxCandidatesPerPixel,
                                 uint64_t max_entries = kMaxCandidateEntries);

}  // namespace ht
