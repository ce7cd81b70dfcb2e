#include "render/primitive_images.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <thread>

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

namespace {
std::atomic<int> host_threads_set{0};
}
int host_threads() {
    const int set = host_threads_set.load(std::memory_order_relaxed);
    return set > 0 ? set : int(std::max(1u, std::min(std::thread::hardware_concurrency(), 8u)));
}
void set_host_threads(int threads) { host_threads_set.store(std::max(0, threads), std::memory_order_relaxed); }

PrimitiveStarts primitive_starts(const SceneGeometry& g) {
    PrimitiveStarts s;
    s.primitive.assign(g.points.size(), kNoPrimitive);
    s.vertices.assign(g.points.size(), 0);
    in_parallel(g.segments.size(), [&](int, size_t begin, size_t end) {
        for (size_t k = begin; k < end; ++k) {  // a point begins at most one primitive
            const HtSegment& seg = g.segments[k];
            s.primitive[seg.point] = uint32_t(k);
            s.vertices[seg.point] = ht_seg_flags(seg) & HT_SEG_TRIANGLE ? 3 : 2;
        }
    });
    return s;
}

double ball_radius(const SceneGeometry& g, size_t i) {
    double r = g.points[i].r;
    if (i > 0) r = std::max(r, double(g.points[i - 1].r));
    if (i + 1 < g.points.size()) r = std::max(r, double(g.points[i + 1].r));
    return r;
}

void PrimitiveImage::box(double* r) const {
    r[0] = std::min(a[0], b[0]), r[1] = std::max(a[1], b[1]);
    r[2] = std::min(a[2], b[2]), r[3] = std::max(a[3], b[3]);
}

ProjectedPrimitives project_primitives(const HtCamera& camera, const SceneGeometry& g, const PrimitiveStarts* given,
                                       double widen) {
    const int w = int(camera.width), h = int(camera.height);
    const CameraFrame frame(camera);
    ProjectedPrimitives out, unbounded;
    out.width = unbounded.width = w, out.height = unbounded.height = h;
    if (!frame.ok) return out;
    // A ball of radius r maps to an ellipsoid whose extent along frame coordinate i is
    // r |row i of the inverse|.
    const glm::dmat3 rows = glm::transpose(frame.inv);  // glm's matrices are column-major
    const double row_norm[3] = {glm::length(rows[0]), glm::length(rows[1]), glm::length(rows[2])};
    for (int i = 0; i < 3; ++i) out.depth_row[i] = rows[0][i];

    // Per point, the image of a ball around it whose radius is the largest of its own and its
    // two neighbours' (a capsule's hit radius is the mean of its two: this covers it at both
    // ends): its side of the eye's plane, and for a ball in front the bounds of its NDC x and y,
    // from the intervals of depth z and lateral coordinates a, b (a / z is monotone in each for
    // z > 0).  A primitive lies inside the convex hull of its vertices' balls, and each bound is a
    // linear-fractional function along it, with its extremes at the vertices: the hull of the
    // vertices' bounds bounds the primitive's image.  Depth is linear, so the nearest of the
    // balls' is the primitive's nearest.
    enum Side : uint8_t { kBehind, kStraddles, kInFront, kNotFinite };
    // point i's side and, in front, its bounds: NDC x0, x1, y0, y1 and the nearest depth (made
    // for each primitive at the point, rather than kept per point: the array cost more in fresh
    // pages than the arithmetic twice)
    const auto point_image = [&](size_t i, double* o) {
        const HtPoint& p = g.points[i];
        const double r = ball_radius(g, i) + widen;
        const glm::dvec3 x = frame.map(p.x, p.y, p.z);
        if (!(std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]) && std::isfinite(r))) return kNotFinite;
        const double z0 = x[0] - r * row_norm[0], z1 = x[0] + r * row_norm[0];
        if (!(z1 > 0)) return kBehind;
        if (!(z0 > 0)) return kStraddles;
        const double a0 = x[1] - r * row_norm[1], a1 = x[1] + r * row_norm[1];
        const double b0 = x[2] - r * row_norm[2], b1 = x[2] + r * row_norm[2];
        o[0] = std::min(a0 / z0, a0 / z1);
        o[1] = std::max(a1 / z0, a1 / z1);
        o[2] = std::min(b0 / z0, b0 / z1);
        o[3] = std::max(b1 / z0, b1 / z1);
        o[4] = z0;
        return kInFront;
    };
    PrimitiveStarts made;
    if (!given) made = primitive_starts(g);
    const PrimitiveStarts& starts = given ? *given : made;
    out.bounded = images_in_point_order(starts, out.images, [&](size_t first, uint32_t k, uint32_t n, PrimitiveImage* im) {
        double bounds[3][5];
        int behind = 0, in_front = 0;
        for (uint32_t v = 0; v < n; ++v) {
            const Side sd = point_image(first + v, bounds[v]);
            if (sd == kNotFinite || sd == kStraddles) return ImageMade::Unbounded;  // nothing can be proved
            behind += sd == kBehind, in_front += sd == kInFront;
        }
        if (in_front == 0) return ImageMade::Drop;       // wholly behind the eye's plane
        if (behind > 0) return ImageMade::Unbounded;     // crosses it: its projection is unbounded
        double sx0 = HUGE_VAL, sx1 = -HUGE_VAL, sy0 = HUGE_VAL, sy1 = -HUGE_VAL, z = HUGE_VAL;
        for (uint32_t v = 0; v < n; ++v) {
            const double* o = bounds[v];
            sx0 = std::min(sx0, o[0]), sx1 = std::max(sx1, o[1]);
            sy0 = std::min(sy0, o[2]), sy1 = std::max(sy1, o[3]);
            z = std::min(z, o[4]);
        }
        // NDC -> pixel coordinates, as kernels/camera.h maps them the other way (y downwards),
        // rounded outwards to float.  A capsule keeps its two ends' bounds: the hull of the two
        // is tighter than their box for a diagonal segment (PrimitiveImage::row_span); a
        // triangle's ends are both its box.
        im->primitive = k;
        im->depth = round_down(z);
        for (uint32_t v = 0; v < 2; ++v) {
            double e[4] = {sx0, sx1, sy0, sy1};
            if (n == 2) std::copy_n(bounds[v], 4, e);
            float* out_end = v == 0 ? im->a : im->b;
            out_end[0] = round_down((e[0] + 1) * 0.5 * w), out_end[1] = round_up((e[1] + 1) * 0.5 * w);
            out_end[2] = round_down((1 - e[3]) * 0.5 * h), out_end[3] = round_up((1 - e[2]) * 0.5 * h);
        }
        double box[4];
        im->box(box);
        if (box[1] + kFootprintMarginPixels < 0 || box[3] + kFootprintMarginPixels < 0 ||
            box[0] - kFootprintMarginPixels >= w || box[2] - kFootprintMarginPixels >= h)
            return ImageMade::Drop;  // off the image even with the widest margin
        return ImageMade::Keep;
    });
    if (!out.bounded) return unbounded;
    return out;
}

bool images_in_point_order(const PrimitiveStarts& starts, BulkVector<PrimitiveImage>& out,
                           const std::function<ImageMade(size_t, uint32_t, uint32_t, PrimitiveImage*)>& make) {
    const size_t np = starts.primitive.size(), threads = size_t(host_threads());
    // each thread's share of the points gets a region of out as long as its primitives
    std::vector<size_t> region(threads + 1, 0), kept(threads, 0);
    std::vector<uint8_t> unbounded(threads, 0);
    in_parallel(np, [&](int t, size_t begin, size_t end) {
        size_t c = 0;
        for (size_t i = begin; i < end; ++i) c += starts.primitive[i] != kNoPrimitive;
        region[size_t(t) + 1] = c;
    });
    for (size_t t = 0; t < threads; ++t) region[t + 1] += region[t];
    out.resize(region[threads]);
    in_parallel(np, [&](int t, size_t begin, size_t end) {
        PrimitiveImage* o = out.data() + region[size_t(t)];
        size_t m = 0;
        for (size_t first = begin; first < end; ++first) {
            const uint32_t k = starts.primitive[first];
            if (k == kNoPrimitive) continue;
            const ImageMade made = make(first, k, starts.vertices[first], o + m);
            if (made == ImageMade::Unbounded) {
                unbounded[size_t(t)] = 1;
                return;
            }
            m += made == ImageMade::Keep;
        }
        kept[size_t(t)] = m;
    });
    for (uint8_t u : unbounded)
        if (u) return false;
    size_t at = 0;  // the regions' kept images closed up, in order
    for (size_t t = 0; t < threads; ++t) {
        if (at != region[t]) std::memmove(out.data() + at, out.data() + region[t], kept[t] * sizeof(PrimitiveImage));
        at += kept[t];
    }
    out.resize(at);
    return true;
}

bool PrimitiveImage::row_span(int y, double margin, int w, int* x_first, int* x_last) const {
    // The hull of boxes a and b is the union over s in [0, 1] of the box (1 - s) a + s b, whose
    // bounds are linear in s: the row's slab [y - margin, y + 1 + margin] meets it for s with
    // y0(s) <= y + 1 + margin and y1(s) >= y - margin, an interval, at whose ends x0(s) and x1(s)
    // take their extremes.
    double s0 = 0, s1 = 1;
    const double top = y + 1 + margin, bottom = y - margin;
    const auto keep = [&](double v0, double dv, double limit, bool below) {
        // v0 + s dv <= limit (below) or >= limit
        if (dv == 0) {
            if (below ? !(v0 <= limit) : !(v0 >= limit)) s1 = -1;
            return;
        }
        const double s = (limit - v0) / dv;
        if ((dv > 0) == below) s1 = std::min(s1, s);
        else s0 = std::max(s0, s);
    };
    keep(a[2], double(b[2]) - a[2], top, true);
    keep(a[3], double(b[3]) - a[3], bottom, false);
    if (!(s0 <= s1)) return false;
    const double dx0 = double(b[0]) - a[0], dx1 = double(b[1]) - a[1];
    const double x0 = std::min(a[0] + s0 * dx0, a[0] + s1 * dx0) - margin;
    const double x1 = std::max(a[1] + s0 * dx1, a[1] + s1 * dx1) + margin;
    if (x1 < 0 || x0 >= w) return false;
    *x_first = std::max(0, int(std::floor(x0)));
    *x_last = std::min(w - 1, int(std::floor(x1)));
    return *x_first <= *x_last;
}

bool PrimitiveImage::pixel_rect(double margin, int w, int h, int* r) const {
    double box[4];
    this->box(box);
    const double x0 = box[0] - margin, x1 = box[1] + margin, y0 = box[2] - margin, y1 = box[3] + margin;
    if (x1 < 0 || y1 < 0 || x0 >= w || y0 >= h) return false;
    r[0] = std::max(0, int(std::floor(x0))), r[1] = std::min(w - 1, int(std::floor(x1)));
    r[2] = std::max(0, int(std::floor(y0))), r[3] = std::min(h - 1, int(std::floor(y1)));
    return true;
}

}  // namespace ht
