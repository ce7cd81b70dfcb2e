// The images of a scene's primitives on a grid: on the camera's pixels (project_primitives; also a
// point light's shadow grid, as a camera at the light) or, projected along a directional light, on
// its shadow grid's cells (render/shadow_lists.h).  A
// capsule or a triangle lies in the convex hull of balls around its vertices, and its image in
// the hull of theirs; the images bound where rays can meet each primitive.  Used for the pixels
// that see no geometry (render/pixel_footprint.h) and the per-pixel or per-cell candidate lists
// (render/candidate_lists.h).
#pragma once

#include "bvh/bvh.h"
#include "core/bulk_vector.h"
#include "core/parallel.h"
#include "kernels/types.h"

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <thread>
#include <vector>

namespace ht {

// The widest margin any use of the images applies, the empty pixels' (render/pixel_footprint.h):
// project_primitives drops only images that lie off the image even widened by it.
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
    // The pixels [r0, r1] x [r2, r3] (inclusive) of the box widened by `margin` in a w x h image;
    // false for none.
    bool pixel_rect(double margin, int w, int h, int* r) const;
};

// Every primitive's image, in point order, or bounded = false when nothing can be proved (the
// eye among the geometry, a camera frame without an inverse, a non-finite point).  depth_row: a camera ray's depth per unit of t is depth_row . d.
struct ProjectedPrimitives {
    int width = 0, height = 0;
    bool bounded = false;
    BulkVector<PrimitiveImage> images;
    double depth_row[3] = {0, 0, 0};
};
// starts: primitive_starts(geometry) when the caller has made it for other passes too (nullptr:
// made here); widen: world units added to every vertex's ball (a point light's grid widens the
// images by how far beside the line to the light its rays may pass, render/shadow_lists.h).
struct PrimitiveStarts;
ProjectedPrimitives project_primitives(const HtCamera& camera, const SceneGeometry& geometry,
                                       const PrimitiveStarts* starts = nullptr, double widen = 0);

// Shared with the light's grids (render/shadow_lists.h):
// the primitive beginning at each point (kNoPrimitive: none) and its vertex count (2 or 3),
// gathered once from the leaf order so the passes over primitives can run in point order;
constexpr uint32_t kNoPrimitive = 0xFFFFFFFFu;
struct PrimitiveStarts {
    std::vector<uint32_t> primitive;
    std::vector<uint8_t> vertices;
};
PrimitiveStarts primitive_starts(const SceneGeometry& geometry);
// every primitive's image in the order of its first point, made by make(first point, primitive,
// vertex count, &image): Keep, Drop (it has none) or Unbounded (nothing can be proved: returns
// false).  Each thread writes its share of the points' images in place and the gaps are closed
// after: no image is copied but those of the later shares, and no array is made per point;
enum class ImageMade { Keep, Drop, Unbounded };
bool images_in_point_order(const PrimitiveStarts& starts, BulkVector<PrimitiveImage>& out,
                           const std::function<ImageMade(size_t, uint32_t, uint32_t, PrimitiveImage*)>& make);
// the radius of the ball around point i that covers every primitive's surface there: the largest
// of its own and its neighbours' (a capsule's hit radius is the mean of its two ends');
double ball_radius(const SceneGeometry& geometry, size_t i);
// double -> float rounded down / up (one float step past the nearest float when that is on the
// wrong side; by bits, as std::nextafter was a quarter of the projection's time; inline, as the
// calls were a tenth of the shadow lists' time);
inline float float_step(float f, bool towards_positive) {
    if (!std::isfinite(f)) return f;
    if (f == 0.0f) return towards_positive ? std::numeric_limits<float>::denorm_min() : -std::numeric_limits<float>::denorm_min();
    uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    bits = (f > 0.0f) == towards_positive ? bits + 1 : bits - 1;
    std::memcpy(&f, &bits, sizeof bits);
    return f;
}
inline float round_down(double x) {
    const float f = float(x);
    return double(f) > x ? float_step(f, false) : f;
}
inline float round_up(double x) {
    const float f = float(x);
    return double(f) < x ? float_step(f, true) : f;
}
// the host's threads for these loops (at most 8; a test may set another count, 0 restoring the
// machine's, to show that the results do not depend on it), and body(thread, begin, end) over
// their contiguous shares of [0, n) in parallel.
int host_threads();
void set_host_threads(int threads);
template <typename Body>
void in_parallel(size_t n, const Body& body) {
    in_parallel(n, host_threads(), body);
}
// body(thread, item) for every item of [0, n), each taken by whichever thread is free: for items
// of unequal work (the lists' bands, whose rows may hold most of the geometry or none).  The
// results must not depend on which thread ran an item.
template <typename Body>
void each_in_parallel(size_t n, const Body& body) {
    std::atomic<size_t> next{0};
    in_parallel(size_t(host_threads()), [&](int t, size_t, size_t) {
        for (size_t item = next++; item < n; item = next++) body(t, item);
    });
}

}  // namespace ht
