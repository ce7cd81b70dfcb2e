// How many bounces a scene needs, from its materials (Zinke 2004 §5): light that has crossed k
// fibres forward keeps about AFS_TT^avg(theta = 0)^k of its energy.  The default depth is the
// first k at which that share falls under kDepthThreshold for every material and channel.
#pragma once

#include "scene/scene.h"

#include <string>

namespace ht {

constexpr double kDepthThreshold = 0.2;  // the paper's own yardstick: 0.7067^5 = 17.6 % "still visible"
constexpr int kMaxAutoDepth = 16;

struct DepthChoice {
    int depth = 1;
    std::string why;  // one line for the log
};

DepthChoice choose_max_depth(const Scene& scene);

}  // namespace ht
