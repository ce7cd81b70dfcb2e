// Time to the first image, the cost a user pays before any sample: process start, scene load,
// BVH build, kernel compilation and one 64 x 64 sample pass, measured in fresh processes so that
// nothing the measuring process has compiled or loaded counts.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace ht {

// Runs `exe render scene --width 64 --height 64 --spp 1` reps times with empty program caches
// (hairtrace's and PoCL's, both in a fresh temporary folder each time) and reps times from the
// binary cache; reports the medians of wall seconds and of the kernel build's share.  Throws
// std::runtime_error when a render fails.
nlohmann::json measure_startup(const std::string& exe, const std::string& scene, int reps, bool print);

}  // namespace ht
