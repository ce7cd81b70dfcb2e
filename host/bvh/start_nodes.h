// Where a path ray's traversal starts: at the node whose leaf held its path's last hit
// (kernels/geometry/bvh_traverse.h ht_traverse_from).  The traversal names that node; a hit found
// without the tree (a camera ray's candidate list) gets it from leaf_entry_nodes.  And the file of
// them: `render --dump-rays` writes, beside a bounce's closest-hit .rays file, the node each ray's
// traversal began at, so that `bench --rays` can time the renderer's traversal of those rays as
// the render runs it, next to the traversal from the root.  The nodes belong to one tree: the file
// carries its hash, and a reader with another tree must not use them.
//
// File layout (little-endian): "HTST", version 1, ray count, node record count (uint32 each), the
// tree's hash (uint64, tree_hash below), then one uint32 node reference per ray (0 = the root).
#pragma once

#include "bvh/bvh.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ht {

// For each entry of the leaf segment array, the reference (as a child slot holds it, the oriented
// flag included) of the node whose leaf slot holds it.
std::vector<uint32_t> leaf_entry_nodes(const SceneGeometry& geometry);

// 0 (the root) and every inner node reference of the tree.
std::vector<uint32_t> start_node_refs(const SceneGeometry& geometry);

// DIR/x.b1.closest.rays -> DIR/x.b1.closest.starts
std::string start_nodes_path(const std::string& rays_path);

// FNV-1a of the node array: the tree the references point into.
uint64_t tree_hash(const SceneGeometry& geometry);

// Throws std::runtime_error naming the file.
void write_start_nodes(const std::string& path, const SceneGeometry& geometry, const std::vector<uint32_t>& starts);

// The references of `path` for `rays` rays, checked against `geometry`: empty when the file is
// absent, or when it was written for another tree (a render with other BVH options than the
// reader's; *other_tree then says so); throws SceneError (exit 2) when it is truncated, lies about
// its counts or names a node that is no inner node of this tree.
std::vector<uint32_t> read_start_nodes(const std::string& path, const SceneGeometry& geometry, size_t rays,
                                       std::string* other_tree);

}  // namespace ht
