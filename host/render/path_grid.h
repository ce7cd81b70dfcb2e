// A uniform grid of capsule lists for the path rays' closest hits (kernels/geometry/path_grid.h
// walks it).  Path rays start on a fibre inside the hair and their next hit is a few radii away
// (the anchor strand's bounce-1 rays: median 2.3 radii); the tree finds it by descending from the
// node of the last hit, then from the root, through boxes that all hold the origin, while a grid
// reaches the origin's cell in one step and tests the capsules around it in the order the ray
// meets them (host/bvh/NOTES.md "A uniform grid for path rays").  Extra memory: one start per cell
// and one entry per capsule and cell it overlaps (18-65 bytes per segment on the scenes measured,
// at most 4 x (kMaxPathGridCellsPerSegment + kPathGridMaxEntriesPerCapsule) = 72).
#pragma once

#include "bvh/bvh.h"
#include "core/bulk_vector.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ht {

struct PathGrid {
    HtPathGrid grid{};                // the cells (kernels/types.h)
    // Bulk arrays (core/bulk_vector.h): filled by the threads that make them, in huge pages, and on a
    // CPU device read in place by the kernels (the render's list_array) rather than copied.
    BulkVector<uint32_t> cell_start;  // cells + 1 offsets into entries (cell c: [start[c], start[c+1]))
    BulkVector<uint32_t> entries;     // leaf record indices (SceneGeometry::segments), per cell ascending

    size_t occupied = 0;  // cells with at least one entry, counted as the starts are laid out

    bool empty() const { return cell_start.empty(); }
    size_t cells() const { return cell_start.empty() ? 0 : cell_start.size() - 1; }
    size_t bytes() const { return 4 * (cell_start.size() + entries.size()); }
    // Its largest array, which one device buffer must hold (the walk reads them unpaged), and
    // whether a device allocating at most max_alloc bytes per buffer (0: no limit) takes it.
    size_t largest_array_bytes() const { return 4 * std::max(cell_start.size(), entries.size()); }
    bool fits_buffers(uint64_t max_alloc) const { return !max_alloc || largest_array_bytes() <= max_alloc; }
    size_t occupied_cells() const { return occupied; }
};

// The cell edge of one segment per cell over the capsules' bounding box: (box volume / segments)^(1/3);
// 0 for a scene without capsules.
float path_grid_cell(const SceneGeometry& geometry);

// The grid of `geometry`'s capsules with cells of edge `cell` (at most kMaxPathGridCellsPerSegment
// cells per segment: a larger cell where the box would need more).  Empty for a scene with
// triangles (their leaf test is the tree's alone), without capsules, or with cell <= 0.
constexpr double kMaxPathGridCellsPerSegment = 4.0;
PathGrid build_path_grid(const SceneGeometry& geometry, float cell);

// The render's grid: cells of kPathGridCellScale x path_grid_cell, 1.25x larger while a sample of the
// capsules would each be listed in more than kPathGridMaxEntriesPerCapsule cells (long segments in
// dense hair), then 1.5x larger while fewer than kPathGridMinEntriesPerCell capsules share a cell
// that holds any (a lock whose box is mostly empty, as a ball of curls: its rays cross many empty
// cells).  Measured on five scenes (docs/PERFORMANCE.md section 1 "Path rays from a uniform grid").
constexpr double kPathGridCellScale = 0.7, kPathGridMaxEntriesPerCapsule = 14.0, kPathGridMinEntriesPerCell = 6.0;
PathGrid build_path_grid(const SceneGeometry& geometry);

// --path-rays auto takes the grid when the path rays a render may trace (spp x pixels x (depth - 1))
// reach this many per segment (docs/PERFORMANCE.md section 1 "Path rays from a uniform grid"), and
// for at most kPathGridAutoMaxSegments segments: the grid, up to 72 bytes per segment, stays under
// 256 MiB, so a scene that fits a device without it is not refused for it (the trace program is
// compiled for the grid or without it before the device's memory is planned).
constexpr double kPathGridRaysPerSegment = 8.0;
// ... and when at least this share of the grid's cells hold capsules: two copies of the anchor
// strand side by side in one box, 16 spp, path stage tree / grid (s): 4.7 % of the cells occupied
// 0.81 / 0.67, 2.8 % 0.79 / 0.78, 1.8 % 0.76 / 0.94, 1.2 % 0.80 / 1.13 (docs/PERFORMANCE.md
// section 1 "Hair in clumps far apart").
constexpr double kPathGridMinOccupiedShare = 0.03;
constexpr size_t kPathGridAutoMaxSegments = (size_t(256) << 20) / 72;  // 3.7 M

}  // namespace ht
