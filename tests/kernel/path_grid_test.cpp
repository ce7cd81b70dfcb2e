// The path rays' uniform grid (render/path_grid.h, kernels/geometry/path_grid.h): the walk finds the
// tree's answer, bit for bit (the capsule, at a tie too, and its t; as a shadow ray, its occlusion),
// for rays leaving the fibres in random directions as path rays do, for rays from outside the grid,
// along the axes and with a short tmax, at cells from a tenth of a segment to one cell for the
// whole scene; and the builder lists every capsule in ascending order in every cell it may meet a
// ray in.
#include <gtest/gtest.h>

#include "bvh/bvh.h"
#include "kernels/geometry/path_grid.h"
#include "random_strands.h"
#include "render/path_grid.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

namespace {

using ht::SceneGeometry;

// Rays: leaving the closest hits of random rays into random directions (path rays), from far
// outside, along the axes, with a zero component, and with tmax short of some hits.
std::vector<HtRay> test_rays(const SceneGeometry& g, uint32_t seed, size_t n) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<HtRay> rays;
    const auto dir = [&](HtRay& r) {
        double d[3] = {u(rng), u(rng), u(rng)};
        const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        r.dx = float(d[0] / len);
        r.dy = float(d[1] / len);
        r.dz = float(d[2] / len);
    };
    while (rays.size() < n) {
        HtRay r{};
        r.ox = float(3 * u(rng));
        r.oy = float(3 * u(rng));
        r.oz = float(3 * u(rng));
        dir(r);
        r.tmin = 0.0f;
        r.tmax = INFINITY;
        switch (rays.size() % 5) {
        case 1: {  // a path ray: from the surface of this ray's first hit, away in a random direction
            real t;
            const uint32_t b = ht_traverse(g.nodes.data(), g.segments.data(), g.points.data(), r, 0, &t);
            if (b == HT_NO_HIT) continue;
            r.ox += float(r.dx * t);
            r.oy += float(r.dy * t);
            r.oz += float(r.dz * t);
            dir(r);
            r.tmin = 1e-4f;
            break;
        }
        case 2: {  // along an axis, or with one component zero
            const int a = int(rays.size() / 5) % 3;
            float* d[3] = {&r.dx, &r.dy, &r.dz};
            if ((rays.size() / 5) % 2) {
                for (int k = 0; k < 3; ++k) *d[k] = k == a ? (u(rng) < 0 ? -1.0f : 1.0f) : 0.0f;
            } else {
                *d[a] = 0.0f;
                const float l = std::sqrt(r.dx * r.dx + r.dy * r.dy + r.dz * r.dz);
                r.dx /= l;
                r.dy /= l;
                r.dz /= l;
            }
            break;
        }
        case 3: r.tmax = float(1.5 + u(rng)); break;  // ends inside the hair
        case 4: r.ox = float(40 + u(rng)); r.dx = -std::fabs(r.dx) - 0.5f; break;  // from far outside the grid
        default: break;
        }
        rays.push_back(r);
    }
    return rays;
}

void expect_tree_answers(const SceneGeometry& g, const ht::PathGrid& grid, const std::vector<HtRay>& rays,
                         const char* what) {
    ASSERT_FALSE(grid.empty()) << what;
    size_t hits = 0, wrong = 0, occluded = 0, wrong_occlusion = 0;
    for (const HtRay& r : rays) {
        real t0, t1;
        const uint32_t b0 = ht_traverse(g.nodes.data(), g.segments.data(), g.points.data(), r, 0, &t0);
        const uint32_t b1 = ht_grid_closest(g.segments.data(), g.points.data(), grid.cell_start.data(),
                                            grid.entries.data(), grid.grid, r, &t1);
        hits += b0 != HT_NO_HIT;
        if (b1 != b0 || (b0 != HT_NO_HIT && t1 != t0)) ++wrong;
        // as a shadow ray: the same occlusion as the tree's any-hit traversal
        const uint32_t o0 = ht_trace_any(g.nodes.data(), g.segments.data(), g.points.data(), r);
        const uint32_t o1 = ht_grid_occluded(g.segments.data(), g.points.data(), grid.cell_start.data(),
                                             grid.entries.data(), grid.grid, r);
        occluded += o0;
        wrong_occlusion += o1 != o0;
    }
    EXPECT_EQ(wrong, 0u) << what << ": " << rays.size() << " rays";
    EXPECT_EQ(wrong_occlusion, 0u) << what << ": " << rays.size() << " rays as shadow rays";
    EXPECT_GT(hits, rays.size() / 20) << what;  // not a test of empty space alone
    EXPECT_EQ(occluded, hits) << what;          // a ray is blocked where it has a closest hit
}

}  // namespace

TEST(PathGrid, WalkFindsTheTreesHitsAtEveryCellSize) {
    // dense: 400 strands of 12 segments of 0.1 in the cube of side 2, radius 0.01
    const SceneGeometry g = ht::build_geometry(httest::random_strands(5, 400, 12, 0.1, 0.01), {});
    const std::vector<HtRay> rays = test_rays(g, 6, 20000);
    const float base = ht::path_grid_cell(g);
    ASSERT_GT(base, 0.0f);
    expect_tree_answers(g, ht::build_path_grid(g), rays, "the render's grid");
    for (const float scale : {0.25f, 1.0f, 3.0f}) expect_tree_answers(g, ht::build_path_grid(g, base * scale), rays, "scaled cells");
    expect_tree_answers(g, ht::build_path_grid(g, 100.0f), rays, "one cell");
    expect_tree_answers(g, ht::build_path_grid(g, 0.01f), rays, "cells of a tenth of a segment (capped)");
}

TEST(PathGrid, WalkFindsTheTreesHitsWithVaryingRadiiAndLongSegments) {
    const SceneGeometry g = ht::build_geometry(httest::random_strands(9, 60, 6, 0.8, 0.03, 0.4, 1.0, 0.5), {});
    expect_tree_answers(g, ht::build_path_grid(g), test_rays(g, 10, 10000), "long segments, radii +-50 %");
}

TEST(PathGrid, EveryCapsuleListedInAscendingOrderWithinTheCellCap) {
    const SceneGeometry g = ht::build_geometry(httest::random_strands(3, 200, 10, 0.1, 0.01), {});
    for (const float cell : {ht::path_grid_cell(g), 0.001f}) {
        const ht::PathGrid grid = ht::build_path_grid(g, cell);
        ASSERT_FALSE(grid.empty());
        const HtPathGrid& p = grid.grid;
        EXPECT_EQ(grid.cells(), size_t(p.dims[0]) * p.dims[1] * p.dims[2]);
        EXPECT_LE(double(grid.cells()), ht::kMaxPathGridCellsPerSegment * double(g.segments.size()) + 1);
        EXPECT_EQ(grid.cell_start.back(), grid.entries.size());
        std::vector<int> listed(g.segments.size(), 0);
        for (size_t c = 0; c < grid.cells(); ++c) {
            ASSERT_LE(grid.cell_start[c], grid.cell_start[c + 1]);
            for (uint32_t i = grid.cell_start[c]; i < grid.cell_start[c + 1]; ++i) {
                ASSERT_LT(grid.entries[i], g.segments.size());
                if (i > grid.cell_start[c]) {
                    EXPECT_LT(grid.entries[i - 1], grid.entries[i]);
                }
                listed[grid.entries[i]] = 1;
            }
        }
        EXPECT_EQ(std::count(listed.begin(), listed.end(), 0), 0);
        EXPECT_GT(grid.occupied_cells(), 0u);
        EXPECT_EQ(grid.bytes(), 4 * (grid.cell_start.size() + grid.entries.size()));
    }
}

// Every point of a capsule's surface lies in a cell that lists it: checked at random surface points
// of every capsule at cells from a tenth of a segment (capsules spanning hundreds of cells) to three
// segments (a few cells each), so both ways the builder collects a capsule's cells are covered.
TEST(PathGrid, EveryCellACapsulesSurfaceReachesListsIt) {
    // long segments of varying radius (as the walk's second test): several pieces per capsule
    const SceneGeometry g = ht::build_geometry(httest::random_strands(9, 60, 6, 0.8, 0.03, 0.4, 1.0, 0.5), {});
    const float base = ht::path_grid_cell(g);
    std::mt19937 rng(11);
    std::normal_distribution<double> n01;
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    for (const float scale : {0.05f, 0.2f, 0.5f, 1.0f, 3.0f}) {
        const ht::PathGrid grid = ht::build_path_grid(g, base * scale);
        ASSERT_FALSE(grid.empty());
        const HtPathGrid& p = grid.grid;
        size_t missing = 0, checked = 0;
        for (uint32_t k = 0; k < g.segments.size(); ++k) {
            const HtPoint& a = g.points[g.segments[k].point];
            const HtPoint& b = g.points[g.segments[k].point + 1];
            for (int i = 0; i < 64; ++i) {
                const double t = u01(rng), r = 0.5 * (double(a.r) + b.r);  // the leaf test's capsule radius
                double v[3] = {n01(rng), n01(rng), n01(rng)};
                const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
                const double q[3] = {a.x + t * (b.x - a.x) + r * v[0] / l, a.y + t * (b.y - a.y) + r * v[1] / l,
                                     a.z + t * (b.z - a.z) + r * v[2] / l};
                uint32_t c[3];
                for (int x = 0; x < 3; ++x) {
                    const int ci = int(std::floor((q[x] - p.lo[x]) * p.inv_cell));
                    ASSERT_GE(ci, 0);
                    ASSERT_LT(ci, int(p.dims[x]));
                    c[x] = uint32_t(ci);
                }
                const uint32_t cell = ht_path_grid_cell(p, c[0], c[1], c[2]);
                const auto first = grid.entries.begin() + grid.cell_start[cell], last = grid.entries.begin() + grid.cell_start[cell + 1];
                missing += !std::binary_search(first, last, k);
                ++checked;
            }
        }
        EXPECT_EQ(missing, 0u) << "cells of " << scale << " x one segment's share, " << checked << " surface points";
    }
}

TEST(PathGrid, NoGridWithoutCapsulesOrCell) {
    ht::Strands none;
    none.first_point.push_back(0);
    const SceneGeometry empty = ht::build_geometry(none, {});
    EXPECT_EQ(ht::path_grid_cell(empty), 0.0f);
    EXPECT_TRUE(ht::build_path_grid(empty).empty());
    const SceneGeometry g = ht::build_geometry(httest::random_strands(3, 20, 10, 0.1, 0.01), {});
    EXPECT_TRUE(ht::build_path_grid(g, 0.0f).empty());
    EXPECT_TRUE(ht::build_path_grid(g, NAN).empty());
    EXPECT_TRUE(ht::build_path_grid(g, -1.0f).empty());
}

// Rays a shading bug could hand over (NaN or infinite origin or direction, a zero direction, tmax
// below tmin): the walk answers as the tree does, and ends.
TEST(PathGrid, DegenerateRaysAnswerAsTheTree) {
    const SceneGeometry g = ht::build_geometry(httest::random_strands(4, 100, 10, 0.1, 0.01), {});
    const ht::PathGrid grid = ht::build_path_grid(g);
    ASSERT_FALSE(grid.empty());
    const float nan = NAN, inf = INFINITY;
    std::vector<HtRay> rays;
    const HtRay base{0.1f, 0.2f, 0.3f, 0.0f, 0.6f, 0.0f, 0.8f, inf};
    for (int field = 0; field < 8; ++field)
        for (const float v : {nan, inf, -inf, 0.0f, 1e30f, -1e-30f}) {
            float f[8];
            std::memcpy(f, &base, sizeof f);
            f[field] = v;
            HtRay r;
            std::memcpy(&r, f, sizeof r);
            rays.push_back(r);
        }
    HtRay still = base;
    still.dx = still.dy = still.dz = 0.0f;
    rays.push_back(still);
    for (const HtRay& r : rays) {
        real t0, t1;
        const uint32_t b0 = ht_traverse(g.nodes.data(), g.segments.data(), g.points.data(), r, 0, &t0);
        const uint32_t b1 = ht_grid_closest(g.segments.data(), g.points.data(), grid.cell_start.data(),
                                            grid.entries.data(), grid.grid, r, &t1);
        EXPECT_EQ(b1, b0) << r.ox << " " << r.oy << " " << r.oz << " " << r.tmin << " " << r.dx << " " << r.dy << " "
                          << r.dz << " " << r.tmax;
    }
}
