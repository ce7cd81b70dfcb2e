// The camera's images of the primitives (render/primitive_images.h) and their two uses: a pixel
// called empty (render/pixel_footprint.h) must be one that no camera ray meets geometry in, and a
// pixel's candidate list (render/candidate_lists.h) must hold every primitive its rays meet.
// Checked against brute force -- every capsule and triangle intersected by the camera's own rays
// (kernels/camera.h) at jitters over the whole pixel, its corners and edges included -- on random
// strands seen from random cameras: close, far (sub-pixel fibres), partly behind the eye.
#include <gtest/gtest.h>

#include "../kernel/random_strands.h"
#include "bvh/bvh.h"
#include "kernels/camera.h"
#include "kernels/geometry/bvh_traverse.h"
#include "kernels/geometry/candidate_list.h"
#include "render/candidate_lists.h"
#include "render/pixel_footprint.h"
#include "render/scene_upload.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>

namespace {

using namespace ht;

// strands with radii that differ along them: a box must grow by the larger
Strands random_strands(uint32_t seed, int count, int segments, double length, double radius) {
    return httest::random_strands(seed, count, segments, length, radius, 0.4, 1.0, 0.5);
}

// Whether the camera ray of pixel `pixel` with jitter (jx, jy) meets any primitive, by brute force.
bool ray_meets_geometry(const HtCamera& cam, const SceneGeometry& g, uint32_t pixel, double jx, double jy) {
    const HtRay ray = ht_camera_ray(&cam, pixel % cam.width, pixel / cam.width, jx, jy);
    const real3 o = make_real3(ray.ox, ray.oy, ray.oz), d = make_real3(ray.dx, ray.dy, ray.dz);
    for (const HtSegment& s : g.segments) {
        const HtPoint& a = g.points[s.point];
        const HtPoint& b = g.points[s.point + 1];
        double t;
        if (ht_seg_flags(s) & HT_SEG_TRIANGLE) {
            real b1, b2;
            t = ht_triangle_intersect(o, d, ht_point_pos(a), ht_point_pos(b), ht_point_pos(g.points[s.point + 2]), 0.0,
                                      1e30, &b1, &b2);
        } else {
            t = ht_capsule_intersect(o, d, ht_point_pos(a), ht_point_pos(b), ht_hit_radius(a, b), 1u, 0.0, 1e30);
        }
        if (t < 1e30) return true;
    }
    return false;
}

// Every empty pixel is checked with a 6 x 6 grid of jitters from 0 to 0.99999 and 8 random ones.
void expect_footprint_conservative(const HtCamera& cam, const SceneGeometry& g, const PixelFootprint& f,
                                   const std::string& what) {
    ASSERT_EQ(f.seen.size() + f.empty.size(), size_t(cam.width) * cam.height) << what;
    std::vector<uint8_t> mark(size_t(cam.width) * cam.height, 0);
    for (const auto* list : {&f.seen, &f.empty})
        for (size_t i = 0; i < list->size(); ++i) {
            ASSERT_TRUE(i == 0 || (*list)[i] > (*list)[i - 1]) << what << ": ascending";
            ASSERT_EQ(mark[(*list)[i]]++, 0) << what << ": each pixel once";
        }
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    for (uint32_t pixel : f.empty) {
        for (int a = 0; a < 6; ++a)
            for (int b = 0; b < 6; ++b)
                ASSERT_FALSE(ray_meets_geometry(cam, g, pixel, a * 0.99999 / 5, b * 0.99999 / 5))
                    << what << ": pixel " << pixel << " called empty";
        for (int k = 0; k < 8; ++k)
            ASSERT_FALSE(ray_meets_geometry(cam, g, pixel, u(rng), u(rng))) << what << ": pixel " << pixel;
    }
}

// Both footprints: the images' and, when the camera gets lists, the lists' (a pixel with an empty
// list), which must call empty at least every pixel the images' 1-pixel margin does.
void expect_conservative(const HtCamera& cam, const SceneGeometry& g, const char* what, size_t* empty_out = nullptr,
                         size_t* tighter_out = nullptr) {
    const PixelFootprint from_images = pixel_footprint(cam, g);
    expect_footprint_conservative(cam, g, from_images, what);
    if (empty_out) *empty_out = from_images.empty.size();
    const PixelCandidates lists = pixel_candidates(project_primitives(cam, g));
    if (!lists.enabled) return;
    const PixelFootprint from_lists = pixel_footprint(lists);
    expect_footprint_conservative(cam, g, from_lists, std::string(what) + ", from the lists");
    EXPECT_TRUE(std::includes(from_lists.empty.begin(), from_lists.empty.end(), from_images.empty.begin(),
                              from_images.empty.end()))
        << what << ": the lists call empty every pixel the images do";
    if (tighter_out) *tighter_out = from_lists.empty.size() - from_images.empty.size();
}

HtCamera camera(double eye_x, double eye_y, double eye_z, double fov, int w, int h) {
    Camera c;
    c.eye = {float(eye_x), float(eye_y), float(eye_z)};
    c.target = {0, 0, 0};
    c.yfov_deg = float(fov);
    return make_kernel_camera(c, w, h);
}

}  // namespace

TEST(PixelFootprint, EmptyPixelsMeetNoGeometryUnderBruteForce) {
    const SceneGeometry g = build_geometry(random_strands(3, 30, 6, 0.15, 0.01));
    size_t empty = 0, tighter = 0;
    expect_conservative(camera(0, 0, 4, 40, 48, 32), g, "framing", &empty, &tighter);
    EXPECT_GT(empty, 100u) << "thin strands leave most pixels empty";
    EXPECT_GT(tighter, 0u) << "the lists' margin is 1/64 pixel, the images' 1";
    expect_conservative(camera(0.3, 2.5, 1.5, 70, 40, 40), g, "close and wide");
    size_t far_empty = 0;
    expect_conservative(camera(30, 5, 40, 20, 40, 30), g, "far: fibres below a pixel wide", &far_empty);
    EXPECT_GT(far_empty, 100u);
    // the eye among the strands: a box that reaches the eye's plane makes every pixel seen
    size_t inside_empty = 1;
    expect_conservative(camera(0.1, 0.05, 0.2, 60, 24, 24), g, "eye inside", &inside_empty);
    EXPECT_EQ(inside_empty, 0u);
}

TEST(PixelFootprint, StrandsBehindTheEyeAndTriangles) {
    Strands s = random_strands(5, 12, 4, 0.2, 0.02);
    for (auto& p : s.points) p[2] += 20.0f;  // all behind a camera at z = 10 looking at -z
    Mesh floor;
    floor.positions = {{-1, -1, -1}, {1, -1, -1}, {1, -1, 1}, {-1, -1, 1}};
    floor.indices = {0, 1, 2, 0, 2, 3};
    const SceneGeometry g = build_geometry(s, {floor}, {SurfaceMaterialDesc{}});
    size_t empty = 0;
    const HtCamera cam = camera(0, 0, 10, 30, 32, 32);
    expect_conservative(cam, g, "floor in front, strands behind", &empty);
    const SceneGeometry behind = build_geometry(s);
    EXPECT_EQ(pixel_footprint(cam, behind).seen.size(), 0u) << "nothing in front of the eye";
    EXPECT_GT(empty, 0u);
    EXPECT_LT(empty, size_t(32 * 32)) << "the floor is in view";
}

TEST(PixelFootprint, DegenerateCameraAndNonFiniteGeometrySeeEverything) {
    const SceneGeometry g = build_geometry(random_strands(9, 4, 3, 0.1, 0.01));
    HtCamera flat = camera(0, 0, 5, 30, 16, 16);
    for (int i = 0; i < 3; ++i) flat.up[i] = flat.right[i];  // a frame without an inverse
    EXPECT_EQ(pixel_footprint(flat, g).empty.size(), 0u);
    SceneGeometry bad = g;
    bad.points[0].x = NAN;
    EXPECT_EQ(pixel_footprint(camera(0, 0, 5, 30, 16, 16), bad).empty.size(), 0u);
}

// ---- the camera rays' candidate lists (pixel_candidates) ------------------------------------

namespace {

// Every pixel with a list: at jitters over the whole pixel (a 4 x 4 grid from 0 to 0.99999 and 4
// random ones), every primitive the camera ray meets (brute force) is in the list, and the list's
// closest hit (kernels/geometry/candidate_list.h) is the tree's, the same primitive at the same t.
// Lists run nearest first.  *hits_out: how many rays met something.
void expect_lists_hold_the_hits(const HtCamera& cam, const SceneGeometry& g, const PixelCandidates& c, const char* what,
                                size_t* hits_out = nullptr) {
    const size_t pixels = size_t(cam.width) * cam.height;
    ASSERT_TRUE(c.enabled) << what;
    EXPECT_EQ(c.start.size(), pixels);
    EXPECT_EQ(c.count.size(), pixels);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    const real3 depth_row = make_real3(c.depth_row[0], c.depth_row[1], c.depth_row[2]);
    size_t hits = 0;
    for (uint32_t pixel = 0; pixel < pixels; ++pixel) {
        if (c.count[pixel] == kCandidatesUseTree) continue;
        const uint32_t* list = c.primitive.data() + c.start[pixel];
        const float* depth = c.depth.data() + c.start[pixel];
        const uint32_t n = c.count[pixel];
        for (uint32_t i = 1; i < n; ++i) EXPECT_LE(depth[i - 1], depth[i]) << what << ": pixel " << pixel << " nearest first";
        std::vector<std::pair<double, double>> jitters;
        for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b) jitters.push_back({a * 0.99999 / 3, b * 0.99999 / 3});
        for (int k = 0; k < 4; ++k) jitters.push_back({u(rng), u(rng)});
        for (const auto& [jx, jy] : jitters) {
            const HtRay ray = ht_camera_ray(&cam, pixel % cam.width, pixel / cam.width, jx, jy);
            const real3 o = make_real3(ray.ox, ray.oy, ray.oz), d = make_real3(ray.dx, ray.dy, ray.dz);
            for (uint32_t k = 0; k < g.segments.size(); ++k) {
                const HtSegment& s = g.segments[k];
                const HtPoint& a = g.points[s.point];
                const HtPoint& b = g.points[s.point + 1];
                double t;
                if (ht_seg_flags(s) & HT_SEG_TRIANGLE) {
                    real b1, b2;
                    t = ht_triangle_intersect(o, d, ht_point_pos(a), ht_point_pos(b), ht_point_pos(g.points[s.point + 2]),
                                              0.0, 1e30, &b1, &b2);
                } else {
                    t = ht_capsule_intersect(o, d, ht_point_pos(a), ht_point_pos(b), ht_hit_radius(a, b), 1u, 0.0, 1e30);
                }
                if (t < 1e30) {
                    ASSERT_NE(std::find(list, list + n, k), list + n)
                        << what << ": pixel " << pixel << " misses primitive " << k << " that its ray meets";
                }
            }
            real t_tree, t_list;
            const uint32_t tree = ht_traverse(g.nodes.data(), g.segments.data(), g.points.data(), ray, 0, &t_tree);
            const uint32_t from_list = ht_candidates_closest(g.segments.data(), g.points.data(), list, depth, n, ray,
                                                             depth_row, &t_list);
            ASSERT_EQ(from_list, tree) << what << ": pixel " << pixel;
            ASSERT_EQ(t_list, t_tree) << what << ": pixel " << pixel;
            hits += tree != HT_NO_HIT;
        }
    }
    if (hits_out) *hits_out = hits;
}

// 600 strands in a box 0.4 wide, fibres 0.03 thick: dozens of them under each pixel of the
// cameras below
Strands dense_tuft() { return httest::random_strands(4, 600, 8, 0.05, 0.015, 0.4, 0.2, 0.5); }

}  // namespace

TEST(PixelCandidates, ListsHoldEveryHitAndGiveTheTreesAnswer) {
    const SceneGeometry g = build_geometry(random_strands(3, 30, 6, 0.15, 0.01));
    for (const auto& [cam, what] : {std::pair{camera(0, 0, 4, 40, 48, 32), "framing"},
                                    std::pair{camera(0.3, 2.5, 1.5, 70, 40, 40), "close and wide"},
                                    std::pair{camera(30, 5, 40, 20, 40, 30), "far: fibres below a pixel wide"}}) {
        const PixelCandidates c = pixel_candidates(project_primitives(cam, g));
        EXPECT_EQ(c.tree_pixels, 0u) << what;
        size_t hits = 0;
        expect_lists_hold_the_hits(cam, g, c, what, &hits);
        EXPECT_GT(hits, 20u) << what << ": rays meet the strands";
    }
    // a dense tuft, fibres crossing in depth: long lists, close depths
    const SceneGeometry dense = build_geometry(dense_tuft());
    const HtCamera along = camera(0, 0, 3, 8, 24, 24);
    size_t hits = 0;
    expect_lists_hold_the_hits(along, dense, pixel_candidates(project_primitives(along, dense)), "dense", &hits);
    EXPECT_GT(hits, 500u);
}

TEST(PixelCandidates, TrianglesAndStrandsBehindTheEye) {
    Strands s = random_strands(5, 12, 4, 0.2, 0.02);
    for (size_t i = 0; i < s.points.size(); i += 2) s.points[i][2] += 20.0f;  // some behind the eye: no lists
    Mesh floor;
    floor.positions = {{-1, -1, -1}, {1, -1, -1}, {1, -1, 1}, {-1, -1, 1}};
    floor.indices = {0, 1, 2, 0, 2, 3};
    const HtCamera cam = camera(0, 0.5, 10, 30, 32, 32);
    EXPECT_FALSE(pixel_candidates(project_primitives(cam, build_geometry(s, {floor}, {SurfaceMaterialDesc{}}))).enabled)
        << "segments that cross the eye's plane: nothing can be proved";
    const SceneGeometry g = build_geometry(random_strands(5, 12, 4, 0.2, 0.02), {floor}, {SurfaceMaterialDesc{}});
    size_t hits = 0;
    expect_lists_hold_the_hits(cam, g, pixel_candidates(project_primitives(cam, g)), "strands on a floor", &hits);
    EXPECT_GT(hits, 500u);
}

// Past the cap a pixel keeps the tree; past the budget the cap halves, and below 8 there are no
// lists at all.
TEST(PixelCandidates, CapAndBudget) {
    const SceneGeometry g = build_geometry(dense_tuft());
    const HtCamera cam = camera(0, 0, 3, 8, 24, 24);
    const ProjectedPrimitives projected = project_primitives(cam, g);
    const PixelCandidates full = pixel_candidates(projected);
    ASSERT_TRUE(full.enabled);
    uint32_t longest = 0;
    for (uint32_t n : full.count) longest = std::max(longest, n);
    ASSERT_GT(longest, 16u);
    const PixelCandidates capped = pixel_candidates(projected, 16);
    EXPECT_GT(capped.tree_pixels, 0u);
    EXPECT_LT(capped.primitive.size(), full.primitive.size());
    for (size_t p = 0; p < capped.count.size(); ++p)
        EXPECT_TRUE(capped.count[p] == kCandidatesUseTree ? full.count[p] > 16 : capped.count[p] == full.count[p]);
    expect_lists_hold_the_hits(cam, g, capped, "capped");
    const PixelCandidates budget = pixel_candidates(projected, kMaxCandidatesPerPixel, full.primitive.size() / 2);
    EXPECT_TRUE(budget.enabled);
    EXPECT_LE(budget.primitive.size(), full.primitive.size() / 2);
    EXPECT_LT(budget.max_per_pixel, kMaxCandidatesPerPixel);
    const PixelCandidates tiny = pixel_candidates(projected, kMaxCandidatesPerPixel, 4);
    EXPECT_TRUE(!tiny.enabled || (tiny.primitive.size() <= 4 && tiny.max_per_pixel >= 8)) << "within the budget or none";
    EXPECT_FALSE(pixel_candidates(projected, 4).enabled) << "a cap below 8: no lists";
    // the eye among the strands: no lists
    EXPECT_FALSE(pixel_candidates(project_primitives(camera(0.01, 0.0, 0.02, 60, 16, 16), g)).enabled);
}

// The images and lists are made on several threads, each band's lists by one; the results must
// not depend on how many: the same bytes on 1, 2, 3 and 8 threads.  Each list is nearest first.
TEST(PixelCandidates, SameListsOnAnyThreadCount) {
    const SceneGeometry g = build_geometry(dense_tuft());
    const HtCamera cam = camera(0.2, 0.4, 3, 10, 64, 48);
    struct Made {
        BulkVector<PrimitiveImage> images;
        PixelCandidates lists;
        PixelFootprint footprint;
    };
    std::vector<Made> made;
    for (const int threads : {1, 2, 3, 8}) {
        set_host_threads(threads);
        Made m;
        const ProjectedPrimitives p = project_primitives(cam, g);
        ASSERT_TRUE(p.bounded);
        m.images = p.images;
        m.lists = pixel_candidates(p);
        m.footprint = pixel_footprint(m.lists);
        made.push_back(std::move(m));
    }
    set_host_threads(0);
    const Made& one = made[0];
    ASSERT_TRUE(one.lists.enabled);
    ASSERT_GT(one.lists.primitive.size(), 10000u);
    for (size_t p = 0; p < one.lists.count.size(); ++p) {
        if (one.lists.count[p] == kCandidatesUseTree) continue;
        for (uint32_t j = 1; j < one.lists.count[p]; ++j)
            ASSERT_LE(one.lists.depth[one.lists.start[p] + j - 1], one.lists.depth[one.lists.start[p] + j]) << "pixel " << p;
    }
    for (size_t k = 1; k < made.size(); ++k) {
        const Made& m = made[k];
        ASSERT_EQ(m.images.size(), one.images.size()) << k;
        EXPECT_EQ(0, std::memcmp(m.images.data(), one.images.data(), one.images.size() * sizeof(PrimitiveImage))) << k;
        EXPECT_EQ(m.lists.start, one.lists.start) << k;
        EXPECT_EQ(m.lists.count, one.lists.count) << k;
        EXPECT_TRUE(m.lists.primitive == one.lists.primitive) << k;
        EXPECT_TRUE(m.lists.depth == one.lists.depth) << k;
        EXPECT_EQ(m.footprint.seen, one.footprint.seen) << k;
    }
}
