// For each pixel (or, for a light's shadow grid, each cell) the primitives whose image
// covers it, in the order of their images' depth: the only ones its rays can meet, tested instead
// of the tree (kernels/geometry/candidate_list.h).
#pragma once

#include "core/bulk_vector.h"
#include "render/primitive_images.h"

#include <cstdint>
#include <vector>

namespace ht {

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
// RenderSettings::ListChoice::Auto for camera rays: lists when spp x the image's pixels reaches
// this many per primitive.  Making them costs about as much per primitive as they save per
// camera ray (0.3 us each on pbrt's lock, docs/PERFORMANCE.md section 8), and the pixels that see
// geometry, not known before the projection, were a quarter to a third of the image in the scenes
// measured there ("Camera rays from lists, or not"): 4 put the choice where the lists stopped
// costing time on pbrt's lock and builtin:ball (~16 spp at 256^2) and the anchor's head (beyond
// 64 spp).
constexpr double kCameraListRaysPerPrimitive = 4.0;
// The lists' margin: the bounds are exact but for double rounding; what they must cover is the
// float arithmetic of the kernels' camera rays and capsule roots, relative errors of ~1e-7 of the
// distance, i.e. ~1e-7 radians, against 1/64 of a pixel's angle (3e-5 radians at 256 pixels
// over a 30-degree field, 5e-7 at 16,384).  A wider margin only lengthens the lists: thin
// fibres' entries stay near their true footprints.
constexpr double kCandidateMarginPixels = 1.0 / 64;
struct PixelCandidates {
    bool enabled = false;
    std::vector<uint32_t> start, count;  // per pixel
    BulkVector<uint32_t> primitive;  // leaf index
    BulkVector<float> depth;         // nearest depth, rounded down
    // The camera's lists: the node holding each leaf entry (bvh/start_nodes.h leaf_entry_nodes), where
    // the traversal of the path's next ray starts (kernels/stages/intersect_camera.cl)
    std::vector<uint32_t> leaf_node;
    float depth_row[3] = {0, 0, 0};
    size_t tree_pixels = 0;
    uint32_t max_per_pixel = 0;  // the cap that fit the budget
    uint64_t bytes() const {  // on the device
        return (start.size() + count.size() + primitive.size() + leaf_node.size()) * sizeof(uint32_t) +
               depth.size() * sizeof(float);
    }
};
PixelCandidates pixel_candidates(const ProjectedPrimitives& projected, uint32_t max_per_pixel = kMaxCandidatesPerPixel,
                                 uint64_t max_entries = kMaxCandidateEntries);

}  // namespace ht
