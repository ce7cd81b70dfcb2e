// The geometry hygiene rule shared by every loader (the rule itself is written out at the top of
// hygiene.cpp) and the size limits checked before a loader allocates anything.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace ht {

// Scenes with more points than this are refused: point indices are uint32 on the device and
// signed-int code paths (OpenCL get_global_id arithmetic) must not overflow.
constexpr uint64_t kMaxScenePoints = uint64_t(1) << 31;

// Bytes the Strands arrays need for this many strands and points.
uint64_t strands_bytes(uint64_t strand_count, uint64_t point_count);

// Throws SceneError "<file>: <what> ..." when point_count exceeds kMaxScenePoints or the arrays
// would need more than opt.max_bytes.  `what` describes where the counts come from, e.g.
// "header says 10000 strands and 160000 points".
void check_scene_size(const std::string& file, const std::string& what, uint64_t strand_count,
                      uint64_t point_count, const LoadOptions& opt);

// What sanitize_strands repaired.
struct HygieneReport {
    uint64_t zero_length_segments = 0;  // duplicate points dropped
    uint64_t short_strands = 0;         // strands dropped for having < 2 points
    HygieneReport& operator+=(const HygieneReport& o) {
        zero_length_segments += o.zero_length_segments;
        short_strands += o.short_strands;
        return *this;
    }
};

// Names strand `index` (its index in s as passed in) for error messages, e.g. "strand 12" or
// "mesh 0 \"hair\" primitive 1 strand 3".  Empty = "strand <index>".
using StrandNamer = std::function<std::string(size_t index)>;

// Applies the hygiene rule to s in place (no reallocation).  Throws SceneError naming `file`,
// the strand and the point on refused input; returns what it repaired.
HygieneReport sanitize_strands(Strands& s, const std::string& file, const StrandNamer& namer = {});

// Appends one warning line per kind of repair with its count (nothing when nothing was repaired).
void add_hygiene_warnings(Scene& scene, const std::string& file, const HygieneReport& report);

// The radius of hair whose file stores none: 1/1000 of the largest extent of the finite points'
// bounding box (the fibre-to-scene ratio of the built-in scenes; non-finite points are refused
// later by sanitize_strands), or 1/1000 when the points have no extent.
constexpr float kRadiusPerExtent = 1e-3f;
float radius_from_extent(const std::vector<Vec3f>& points);

// True when the segment a -> b has zero length in single precision (see the rule).
bool is_zero_length_segment(const Vec3f& a, const Vec3f& b);

}  // namespace ht
