#include "render/pixel_footprint.h"

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

namespace ht {

namespace {

// World point -> (depth, depth * sx, depth * sy) in the camera's frame: the ray through NDC
// (sx, sy) runs along forward + right sx + up sy (kernels/camera.h), so a point on it at
// parameter t solves [forward right up] x = p - eye with x = t (1, sx, sy).
struct CameraFrame {
    glm::dvec3 eye;
    glm::dmat3 inv{0.0};
    bool ok = false;

    explicit CameraFrame(const HtCamera& c) : eye(c.eye[0], c.eye[1], c.eye[2]) {
        const glm::dmat3 m(glm::dvec3(c.forward[0], c.forward[1], c.forward[2]),
                           glm::dvec3(c.right[0], c.right[1], c.right[2]), glm::dvec3(c.up[0], c.up[1], c.up[2]));
        double scale = 0;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) scale = std::max(scale, std::fabs(m[i][j]));
        const double det = glm::determinant(m);
        if (!std::isfinite(det) || !(std::fabs(det) > 1e-12 * scale * scale * scale)) return;
        inv = glm::inverse(m);
        ok = true;
    }

    glm::dvec3 map(double x, double y, double z) const { return inv * (glm::dvec3(x, y, z) - eye); }
};

}  // namespace

PixelFootprint pixel_footprint(const HtCamera& camera, const SceneGeometry& g) {
    const int w = int(camera.width), h = int(camera.height);
    std::vector<uint8_t> seen(size_t(w) * size_t(h), 0);
    const CameraFrame frame(camera);
    PixelFootprint f;
    const auto every_pixel = [&] {
        f.seen.resize(seen.size());
        for (size_t i = 0; i < seen.size(); ++i) f.seen[i] = uint32_t(i);
        return f;
    };
    if (!frame.ok) return every_pixel();
    // A ball of radius r maps to an ellipsoid whose extent along frame coordinate i is
    // r |row i of the inverse|.
    const glm::dmat3 rows = glm::transpose(frame.inv);  // glm's matrices are column-major
    const double row_norm[3] = {glm::length(rows[0]), glm::length(rows[1]), glm::length(rows[2])};

    // Per point, the image of a ball around it whose radius is the largest of its own and its
    // two neighbours' (a capsule's hit radius is the mean of its two: this covers it at both
    // ends): its side of the eye's plane, and for a ball in front the bounds of its NDC x and y,
    // from the intervals of depth z and lateral coordinates a, b (a / z is monotone in each for
    // z > 0).  A primitive lies inside the convex hull of its vertices' balls, and each bound is a
    // linear-fractional function along it, with its extremes at the vertices: the hull of the
    // vertices' bounds bounds the primitive's image.
    enum Side : uint8_t { kBehind, kStraddles, kInFront, kNotFinite };
    const size_t np = g.points.size();
    std::vector<uint8_t> side(np);
    std::vector<double> bounds(4 * np);  // NDC x0, x1, y0, y1
    for (size_t i = 0; i < np; ++i) {
        const HtPoint& p = g.points[i];
        double r = p.r;
        if (i > 0) r = std::max(r, double(g.points[i - 1].r));
        if (i + 1 < np) r = std::max(r, double(g.points[i + 1].r));
        const glm::dvec3 x = frame.map(p.x, p.y, p.z);
        if (!(std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]) && std::isfinite(r))) {
            side[i] = kNotFinite;
            continue;
        }
        const double z0 = x[0] - r * row_norm[0], z1 = x[0] + r * row_norm[0];
        side[i] = !(z1 > 0) ? kBehind : !(z0 > 0) ? kStraddles : kInFront;
        if (side[i] != kInFront) continue;
        const double a0 = x[1] - r * row_norm[1], a1 = x[1] + r * row_norm[1];
        const double b0 = x[2] - r * row_norm[2], b1 = x[2] + r * row_norm[2];
        double* o = &bounds[4 * i];
        o[0] = std::min(a0 / z0, a0 / z1);
        o[1] = std::max(a1 / z0, a1 / z1);
        o[2] = std::min(b0 / z0, b0 / z1);
        o[3] = std::max(b1 / z0, b1 / z1);
    }
    // the primitives by their first point, visited in point order: the leaves' order is the BVH's,
    // and reading the points' bounds in it missed the cache on most primitives
    std::vector<uint8_t> vertices(np, 0);
    for (const HtSegment& s : g.segments) vertices[s.point] = s.flags & HT_SEG_TRIANGLE ? 3 : 2;
    for (size_t first = 0; first < np; ++first) {
        const uint32_t n = vertices[first];
        if (n == 0) continue;
        int behind = 0, in_front = 0;
        for (uint32_t v = 0; v < n; ++v) {
            const uint8_t sd = side[first + v];
            if (sd == kNotFinite || sd == kStraddles) return every_pixel();  // nothing can be proved
            behind += sd == kBehind, in_front += sd == kInFront;
        }
        if (in_front == 0) continue;            // wholly behind the eye's plane
        if (behind > 0) return every_pixel();   // crosses it: its projection is unbounded
        double sx0 = HUGE_VAL, sx1 = -HUGE_VAL, sy0 = HUGE_VAL, sy1 = -HUGE_VAL;
        for (uint32_t v = 0; v < n; ++v) {
            const double* o = &bounds[4 * (first + v)];
            sx0 = std::min(sx0, o[0]), sx1 = std::max(sx1, o[1]);
            sy0 = std::min(sy0, o[2]), sy1 = std::max(sy1, o[3]);
        }
        // NDC -> pixel coordinates, as kernels/camera.h maps them the other way (y downwards)
        const double px0 = (sx0 + 1) * 0.5 * w - kFootprintMarginPixels, px1 = (sx1 + 1) * 0.5 * w + kFootprintMarginPixels;
        const double py0 = (1 - sy1) * 0.5 * h - kFootprintMarginPixels, py1 = (1 - sy0) * 0.5 * h + kFootprintMarginPixels;
        if (px1 < 0 || py1 < 0 || px0 >= w || py0 >= h) continue;
        const int ax = std::max(0, int(std::floor(px0))), bx = std::min(w - 1, int(std::floor(px1)));
        const int ay = std::max(0, int(std::floor(py0))), by = std::min(h - 1, int(std::floor(py1)));
        for (int y = ay; y <= by; ++y) std::fill(seen.begin() + size_t(y) * w + ax, seen.begin() + size_t(y) * w + bx + 1, 1);
    }
    for (size_t i = 0; i < seen.size(); ++i) (seen[i] ? f.seen : f.empty).push_back(uint32_t(i));
    return f;
}

}  // namespace ht
