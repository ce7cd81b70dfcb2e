// Shadow rays toward a directional light all run along one direction, so each stays in one cell
// of a grid laid across it: only the primitives whose shadow covers the cell can block it.  Shadow
// rays toward a point or spot light all run to one point, so each stays (within a fibre's width)
// on the line from the light through its origin: seen from the light, the direction of its origin
// picks a cell of the image a camera there would see, and only the primitives whose image covers
// that cell and which lie nearer the light than the origin can block it.  The lists per cell
// (render/candidate_lists.h's builder, the cells in place of pixels, sorted by how far towards a
// directional light each primitive reaches, or by its depth from a point light) let
// kernels/stages/intersect_shadow_lists.cl answer such a ray without the tree, with the tree's
// answer (docs/PERFORMANCE.md section 8 "Shadow rays from per-cell lists").
#pragma once

#include "bvh/bvh.h"
#include "core/bulk_vector.h"
#include "kernels/types.h"

#include <cstdint>
#include <vector>

namespace ht {

// A cell's side in mean fibre radii (measured on pbrt's lock, docs/PERFORMANCE.md section 8),
// the grids' largest side in cells, the lights that get a grid, and the most cells per primitive
// (the cell grows where its radii would make more).
constexpr double kShadowCellRadii = 4.0;
constexpr uint32_t kMaxShadowGridSide = 4096;
constexpr size_t kMaxShadowGrids = 4;
constexpr double kShadowCellsPerPrimitive = 4.0;
// RenderSettings::ShadowLists::Auto: lists when the render's first-vertex shadow rays through
// them (list_shadow_rays_per_path below) reach this many per entry they would hold
// (estimate_shadow_list_entries): between the break-evens measured on four locks at depths 1 and
// 5 (docs/PERFORMANCE.md section 8 "`auto` weighs rays against entries")
constexpr double kShadowListRaysPerEntry = 0.6;

struct ShadowLists {
    std::vector<HtShadowGrid> grids;  // one per light with lists, at most kMaxShadowGrids
    // every grid's cells back to back (HtShadowGrid::cell_offset), as PixelCandidates holds them:
    // cell c's list is entries start[c] .. start[c] + count[c] (count kCandidatesUseTree: the
    // tree).  A directional light's: nearest the light last, key = how far along dir the
    // primitive reaches, rounded up; a point light's: nearest the light first, key = the
    // primitive's nearest depth from it, rounded down
    std::vector<uint32_t> start, count;
    BulkVector<uint32_t> primitive;
    BulkVector<float> key;
    size_t tree_cells = 0;
    bool enabled() const { return !grids.empty(); }
    uint64_t bytes() const;
};

// Whether a light can have shadow lists: directional, point and spot lights (a sphere light's rays
// run to points across its sphere).
bool casts_shadow_lists(const HtLight& light);
// Lists for the first kMaxShadowGrids such lights among `lights`; a light gets none when the
// geometry holds a non-finite point or the lists would not fit kMaxCandidateEntries, and a point
// or spot light none when the geometry is not all in front of it within 63 degrees of one axis
// (a light among the hair; a cube of six images would serve it, not built).
// starts: primitive_starts(geometry) when the caller has made it for the camera too (nullptr:
// made here, once for every light; render/primitive_images.h).
struct PrimitiveStarts;
ShadowLists build_shadow_lists(const SceneGeometry& geometry, const std::vector<HtLight>& lights,
                               double cell_radii = kShadowCellRadii, const PrimitiveStarts* starts = nullptr);

// About as many entries as build_shadow_lists would make (each primitive counted in the cells of
// its shadow's bounding hull), from an even sample of the points and primitives per light: what
// the lists would cost, before they are made (RenderSettings::ShadowLists::Auto).
double estimate_shadow_list_entries(const SceneGeometry& geometry, const std::vector<HtLight>& lights,
                                    double cell_radii = kShadowCellRadii);

// The shadow rays a camera path sends through intersect_shadow at its first vertex, which the
// lists serve: its light samples; none when --indirect afs or dual takes that vertex's rays into
// its own stage (afs at depth 1, dual always).  Later vertices are left out: they added 0.1-1.2
// rays per camera path at depth 5 on the four locks measured, and the threshold was fitted without
// them.
struct RenderSettings;
double list_shadow_rays_per_path(const RenderSettings& settings);

}  // namespace ht
