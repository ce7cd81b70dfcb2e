// Hair geometry for the kernels: strand points, capsule segments in BVH leaf order and the
// 8-wide BVH (kernels/types.h HtBvhNode, children's bounds as SoA).
#pragma once

#include "core/bulk_vector.h"
#include "scene/scene.h"

#include "kernels/types.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ht {


// The binary build tree's depth cap: the builder turns any node deeper than this into a leaf, so
// the 8-wide tree (at least three binary levels per node, at most 7 pushes each) fits the
// traversal's private stack of HT_STACK_SIZE entries (asserted in build.cpp).
constexpr int kMaxBvhDepth = 60;

struct BvhOptions {
    int bins = 16;          // SAH bins per axis (clamped to [4, 64])
    int max_leaf = 8;       // segments per leaf (a leaf may exceed it only at kMaxBvhDepth)
    float c_trav = 1.0f;    // SAH cost of visiting an inner node ...
    float c_isect = 1.5f;   // ... relative to one capsule test
    // The SAH charges c_isect per group of leaf_lanes references, not per reference: the OpenCL
    // leaf test takes eight capsules at once, one per float8 lane (kernels/geometry/bvh_traverse.h
    // ht_intersect_leaf), so a leaf of up to 8 costs one group and leaves fill up to max_leaf
    // (host/bvh/NOTES.md "Leaves tested eight at a time": 7.6 segments per leaf on the strand
    // anchor, 1.06-1.11x per CPU-second on its path rays; with 4, the four-lane groups of before, the
    // tree is the one of "Leaves tested four at a time").  1 = per reference (the scalar leaves'
    // model).
    int leaf_lanes = 8;
    // Early split clipping of long diagonal segments: a segment's box is replaced by the boxes
    // of its halves (recursively, up to split_depth levels) while the halves' summed surface
    // area is below split_ratio x the parent box's.  Each piece is a separate BVH reference to
    // the same segment (a segment may then appear in several leaves).  0 disables.
    float split_ratio = 0.0f;
    int split_depth = 2;
    unsigned threads = 0;   // build threads; 0 = std::thread::hardware_concurrency()
    // Oriented nodes (host/bvh/NOTES.md "Oriented nodes"): a node keeps its children's
    // boxes in a frame along its segments' dominant direction when their count-weighted half-area
    // there is below obb_ratio x the axis-aligned one.  0 = axis-aligned nodes only.  0.8 (the
    // value measured in NOTES.md) is the default: the passes of renders of long fibres take
    // 0.86-0.95x the time with it, those of short-segment locks the same; the build takes longer,
    // so `render --bvh-oriented auto` takes it only for renders long enough to win that back
    // (NOTES.md "Oriented nodes by default").
    float obb_ratio = 0.8f;
    // Oriented splits (host/bvh/NOTES.md "Oriented splits"): with obb_ratio > 0, each binary node
    // of 16 or more references is also binned in the frame of its segments' dominant direction,
    // and split there when that split's count-weighted area is below obb_split x the best
    // axis-aligned one's.  0 = off (hair-only scenes; a scene with triangles is split
    // axis-aligned).
    float obb_split = 0.0f;

    // The defaults: ~7.6 segments per leaf and 41 bytes/segment on the strand anchor, measured
    // faster than scalar leaves of ~1.3 (host/bvh/NOTES.md "Leaves tested four / eight at a time").
    // compact() makes intersections cheap in the SAH so leaves fill up further (43 bytes/segment
    // with scalar leaves; not re-measured with the four-lane test).
    static BvhOptions compact() {
        BvhOptions o;
        o.max_leaf = 8;
        o.c_isect = 0.3f;
        return o;
    }
};

struct BvhStats {
    size_t nodes = 0;       // HtBvhNode records (8-wide inner nodes + one frame per oriented node)
    size_t oriented = 0;    // oriented nodes among them
    size_t oriented_splits = 0;  // binary nodes split in their segments' frame (BvhOptions::obb_split)
    size_t leaves = 0;
    size_t max_depth = 0;
    size_t references = 0;  // leaf entries (= segments unless split_ratio > 0)
    double sah_cost = 0;    // C_trav per inner node + C_isect per reference, area-weighted
    double bytes_per_segment = 0;  // (points + leaf segments + nodes) bytes / segments
    double build_ms = 0;
};

struct SceneGeometry {
    // The three kernel arrays are BulkVectors (core/bulk_vector.h): the build writes them into
    // fresh memory, faulted in 2 MiB at a time; their resize() leaves elements unset.
    // All strand points, strands back to back, then 3 vertices per triangle (r = 0).
    BulkVector<HtPoint> points;
    // Leaf order (kernels/types.h HtSegment: point and strand id | flags; a triangle's strand id
    // is its triangle index).  global_id() gives a record's Embree primID.
    BulkVector<HtSegment> segments;
    BulkVector<HtBvhNode> nodes;     // node 0 = root; never empty
    std::vector<HtTriangleShading> triangles;  // per triangle, meshes back to back
    BvhStats stats;
    size_t segment_count = 0;         // distinct hair segments of the scene
    size_t triangle_count = 0;        // triangles (also the size of `triangles`)
    // Host only, per strand: its first point minus its first segment's global id, so that a
    // capsule's id is point - strand_id_shift[strand] (the kernels need no ids: kernels/types.h).
    std::vector<uint32_t> strand_id_shift;

    // The global id (Embree primID) of leaf record s: capsules strands back to back, then the
    // triangles (segment_count + triangle index).
    uint32_t global_id(const HtSegment& s) const {
        return ht_seg_flags(s) & HT_SEG_TRIANGLE ? uint32_t(segment_count) + ht_seg_strand(s)
                                                 : s.point - strand_id_shift[ht_seg_strand(s)];
    }
};

// Builds points, segments and the BVH for all strands.  Strands with fewer than 2 points have
// no segments.  An empty scene yields a single root with two empty slots.
SceneGeometry build_geometry(const Strands& strands, const BvhOptions& opt = {});
// The same with triangle meshes in the same BVH (one traversal finds both kinds).  Mesh
// indices must be in range (the loaders check); albedo and texture index come from
// surface_materials[material] (a missing material is grey 0.8); a mesh without uvs is untextured.
SceneGeometry build_geometry(const Strands& strands, const std::vector<Mesh>& meshes,
                             const std::vector<SurfaceMaterialDesc>& surface_materials,
                             const BvhOptions& opt = {});
inline SceneGeometry build_geometry(const Scene& scene, const BvhOptions& opt = {}) {
    return build_geometry(scene.strands, scene.meshes, scene.surface_materials, opt);
}

// Rebuilds only the BVH (and the leaf order) of an existing geometry with other options.
void rebuild_bvh(SceneGeometry& geo, const BvhOptions& opt);

}  // namespace ht
