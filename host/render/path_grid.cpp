#include "render/path_grid.h"

#include "render/primitive_images.h"

#include "kernels/geometry/path_grid.h"

#include <algorithm>
#include <cmath>

namespace ht {

namespace {
struct Box {
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    size_t capsules = 0;
};

// The capsules as the leaf test meets them: each of its two points' mean radius around its axis
// (bvh_traverse.h ht_intersect_entries, as the tree's bounds), not each point's own.
Box capsule_box(const SceneGeometry& g) {
    Box b;
    for (const HtSegment& s : g.segments) {
        if (ht_seg_flags(s) & HT_SEG_TRIANGLE) continue;
        ++b.capsules;
        const double r = 0.5 * (double(g.points[s.point].r) + g.points[s.point + 1].r);
        for (uint32_t i = s.point; i <= s.point + 1; ++i) {
            const HtPoint& p = g.points[i];
            const double c[3] = {p.x, p.y, p.z};
            for (int a = 0; a < 3; ++a) {
                b.lo[a] = std::min(b.lo[a], c[a] - r);
                b.hi[a] = std::max(b.hi[a], c[a] + r);
            }
        }
    }
    return b;
}

float cell_for(const Box& b) {
    if (!b.capsules) return 0.0f;
    double volume = 1;
    for (int a = 0; a < 3; ++a) volume *= std::max(b.hi[a] - b.lo[a], 1e-6);
    return float(std::cbrt(volume / double(b.capsules)));
}

// The grid's cells and how far a capsule's cells reach beyond its radius.
struct Layout {
    HtPathGrid grid{};
    double pad = 0;
};

Layout layout_for(const Box& b, double cell) {
    // The padding: more than the walk's rounding (a float position of magnitude |x| is off by
    // ~6e-8 |x|, a cell wall's distance likewise), so that a capsule meeting the ray near a wall is
    // listed on both sides of it.
    double scale = 0;
    for (int a = 0; a < 3; ++a) scale = std::max({scale, std::fabs(b.lo[a]), std::fabs(b.hi[a])});
    Layout l;
    for (;;) {
        l.pad = 1e-5 * scale + 1e-3 * cell;
        double n = 1;
        for (int a = 0; a < 3; ++a) {
            l.grid.dims[a] = uint32_t(std::max(1.0, std::ceil((b.hi[a] - b.lo[a] + 2 * l.pad) / cell)));
            n *= l.grid.dims[a];
        }
        if (n <= kMaxPathGridCellsPerSegment * double(b.capsules) + 1) break;
        cell *= 1.25;
    }
    for (int a = 0; a < 3; ++a) l.grid.lo[a] = float(b.lo[a] - l.pad);
    l.grid.cell = float(cell);
    l.grid.inv_cell = float(1.0 / double(l.grid.cell));
    return l;
}

// floor(x) as an int for |x| < 2^31, inline (std::floor is a library call without SSE4.1).
int floor_int(double x) {
    const int i = int(x);
    return i - (x < double(i));
}

// The cells capsule s may meet a ray in, each once, into `out` (cleared first): its axis cut into
// pieces of at most half a cell, each piece's box grown by the radius and the padding.  Pieces
// overlap in a few cells: where the capsule's whole box spans at most 64 cells (nearly always),
// a bit per cell of that box collects them, else a new cell is compared with those listed.
void capsule_cells(const SceneGeometry& g, const HtSegment& s, const Layout& l, std::vector<uint32_t>& out) {
    out.clear();
    const HtPathGrid& grid = l.grid;
    const double inv = grid.inv_cell;
    const HtPoint& p0 = g.points[s.point];
    const HtPoint& p1 = g.points[s.point + 1];
    const double a[3] = {p0.x, p0.y, p0.z}, e[3] = {double(p1.x) - p0.x, double(p1.y) - p0.y, double(p1.z) - p0.z};
    const double grow = 0.5 * (double(p0.r) + double(p1.r)) * 1.0001 + l.pad;
    const double len = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    const int pieces = std::max(1, int(std::ceil(2.0 * len * inv)));
    // the cells of piece q, per axis [from, to]
    const auto piece_cells = [&](int q, int from[3], int to[3]) {
        for (int x = 0; x < 3; ++x) {
            const double u = a[x] + e[x] * (double(q) / pieces), v = a[x] + e[x] * (double(q + 1) / pieces);
            const int last = int(grid.dims[x]) - 1;
            from[x] = std::clamp(floor_int((std::min(u, v) - grow - grid.lo[x]) * inv), 0, last);
            to[x] = std::clamp(floor_int((std::max(u, v) + grow - grid.lo[x]) * inv), 0, last);
        }
    };
    const auto cell_index = [&](int x, int y, int z) { return ht_path_grid_cell(grid, uint32_t(x), uint32_t(y), uint32_t(z)); };
    // the whole capsule's cells: the first and last pieces' outer bounds (the axis is straight)
    int lo[3], hi[3], f[3], t[3];
    piece_cells(0, lo, hi);
    piece_cells(pieces - 1, f, t);
    for (int x = 0; x < 3; ++x) lo[x] = std::min(lo[x], f[x]), hi[x] = std::max(hi[x], t[x]);
    const int n0 = hi[0] - lo[0] + 1, n1 = hi[1] - lo[1] + 1, n2 = hi[2] - lo[2] + 1;
    if (n0 * n1 * n2 <= 64) {
        uint64_t bits = 0;
        for (int q = 0; q < pieces; ++q) {
            piece_cells(q, f, t);
            for (int z = f[2]; z <= t[2]; ++z)
                for (int y = f[1]; y <= t[1]; ++y)
                    for (int x = f[0]; x <= t[0]; ++x) bits |= uint64_t(1) << (((z - lo[2]) * n1 + (y - lo[1])) * n0 + (x - lo[0]));
        }
        for (; bits; bits &= bits - 1) {
            const int b = __builtin_ctzll(bits), x = b % n0, y = (b / n0) % n1, z = b / (n0 * n1);
            out.push_back(cell_index(lo[0] + x, lo[1] + y, lo[2] + z));
        }
        return;
    }
    for (int q = 0; q < pieces; ++q) {
        piece_cells(q, f, t);
        const size_t before = out.size();  // this piece's cells are distinct among themselves
        for (int z = f[2]; z <= t[2]; ++z)
            for (int y = f[1]; y <= t[1]; ++y)
                for (int x = f[0]; x <= t[0]; ++x) {
                    const uint32_t c = cell_index(x, y, z);
                    if (std::find(out.begin(), out.begin() + before, c) == out.begin() + before) out.push_back(c);
                }
    }
}
// Entries per capsule at cells of `cell`, from an even sample of at most 16,384 capsules (the cells
// of a capsule depend on the cell size and its own length and radius only, not on its neighbours).
double entries_per_capsule(const SceneGeometry& geometry, const Box& b, double cell) {
    const Layout l = layout_for(b, cell);
    const size_t n = geometry.segments.size(), step = std::max<size_t>(1, n / 16384);
    std::vector<uint32_t> cs;
    double entries = 0, sampled = 0;
    for (size_t k = 0; k < n; k += step) {
        capsule_cells(geometry, geometry.segments[k], l, cs);
        entries += double(cs.size());
        sampled += 1;
    }
    return sampled > 0 ? entries / sampled : 0.0;
}

}  // namespace

float path_grid_cell(const SceneGeometry& geometry) { return cell_for(capsule_box(geometry)); }

namespace {
// The grid at cells of `cell` over b = capsule_box(geometry), made once by the caller.
PathGrid grid_in(const SceneGeometry& geometry, const Box& b, float cell);
}  // namespace

PathGrid build_path_grid(const SceneGeometry& geometry) {
    if (geometry.triangle_count) return PathGrid{};
    const Box b = capsule_box(geometry);
    double cell = kPathGridCellScale * cell_for(b);
    if (!(cell > 0)) return PathGrid{};
    // cells much shorter than the capsules list each in many (the anchor's dense head of long
    // segments: 27 per capsule at the scale above, against 12 on the anchor strand and 13 on
    // straight.hair): larger cells until at most kPathGridMaxEntriesPerCapsule
    for (int grow = 0; grow < 8 && entries_per_capsule(geometry, b, cell) > kPathGridMaxEntriesPerCapsule; ++grow)
        cell *= 1.25;
    PathGrid g = grid_in(geometry, b, float(cell));
    for (int grow = 0; grow < 3 && !g.empty() && double(g.entries.size()) < kPathGridMinEntriesPerCell * double(g.occupied_cells()); ++grow) {
        cell *= 1.5;
        g = grid_in(geometry, b, float(cell));
    }
    return g;
}

PathGrid build_path_grid(const SceneGeometry& geometry, float cell) {
    if (geometry.triangle_count) return PathGrid{};
    return grid_in(geometry, capsule_box(geometry), cell);
}

namespace {
PathGrid grid_in(const SceneGeometry& geometry, const Box& b, float cell) {
    PathGrid out;
    if (!(cell > 0.0f) || !std::isfinite(cell) || !b.capsules) return out;
    const Layout l = layout_for(b, cell);
    out.grid = l.grid;
    const size_t cells = size_t(l.grid.dims[0]) * l.grid.dims[1] * l.grid.dims[2];
    const size_t n = geometry.segments.size();

    // Each thread lists the cells of its contiguous share of the leaf records and counts them per
    // cell; a cell's entries are then the threads' in thread order, each thread's in record order:
    // ascending record indices, whatever the thread count.
    const int threads = host_threads();
    std::vector<BulkVector<uint32_t>> listed(threads);
    std::vector<std::vector<uint32_t>> counts(threads), begin(threads);
    in_parallel(n, [&](int t, size_t from, size_t to) {
        BulkVector<uint32_t>& mine = listed[t];
        std::vector<uint32_t>& count = counts[t];
        count.assign(cells, 0);
        begin[t] = {uint32_t(from)};  // records from..to; mine holds their cells back to back
        std::vector<uint32_t> cs;
        std::vector<uint32_t> offsets;
        mine.reserve((to - from) * 16);  // address space only; the builder aims at <= 14 per capsule
        offsets.reserve(to - from + 1);
        offsets.push_back(0);
        for (size_t k = from; k < to; ++k) {
            capsule_cells(geometry, geometry.segments[k], l, cs);  // capsules only (no triangles here)
            for (uint32_t c : cs) ++count[c];
            mine.insert(mine.end(), cs.begin(), cs.end());
            offsets.push_back(uint32_t(mine.size()));
        }
        begin[t].insert(begin[t].end(), offsets.begin(), offsets.end());
    });
    // Cell starts, and where each thread's entries of each cell begin (counts[t] becomes that).
    out.cell_start.resize(cells + 1);  // every start written below
    uint64_t total = 0;
    for (size_t c = 0; c < cells; ++c) {
        out.cell_start[c] = uint32_t(total);
        const uint64_t before = total;
        for (int t = 0; t < threads; ++t) {
            const uint32_t k = counts[t][c];
            counts[t][c] = uint32_t(total);
            total += k;
        }
        out.occupied += total > before;
    }
    if (total > 0xFFFFFFFFull) return PathGrid{};  // past 32-bit offsets: no grid
    out.cell_start[cells] = uint32_t(total);
    out.entries.resize(total);
    in_parallel(n, [&](int t, size_t, size_t) {
        const BulkVector<uint32_t>& mine = listed[t];
        std::vector<uint32_t>& at = counts[t];
        const uint32_t first = begin[t][0];
        const size_t records = begin[t].size() - 2;
        for (size_t r = 0; r < records; ++r)
            for (uint32_t i = begin[t][1 + r]; i < begin[t][2 + r]; ++i) out.entries[at[mine[i]]++] = first + uint32_t(r);
    });
    return out;
}
}  // namespace

}  // namespace ht
