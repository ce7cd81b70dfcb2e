// `hairtrace bench`: BVH build and OpenCL intersection throughput, checked against the Embree
// anchor's ray files when given.
#pragma once

#include "scene/scene.h"

#include <functional>
#include <string>
#include <vector>

namespace ht {

// Turns a scene name ("builtin:strand", "x.hair", ...) into strands.  main wires it to
// ht::load_scene; the default reads .hair files only (bench_read_hair_file).
using SceneSource = std::function<Strands(const std::string&)>;

// args = the command line after "bench":
//   [--hair FILE | --scene NAME]...   scenes (default: builtin:strand builtin:ball)
//   [--rays FILE.rays]...             ray sets for the last scene named before them; without
//                                     any, <dir>/<stem>.{primary,incoherent,shadow}.rays next
//                                     to a .hair file are used if present, else rays are
//                                     generated (camera framing the scene)
//   [--reps N] (5)  [--json]  [--device N]  [--res N] (generated primary rays, 1024)
//   BVH: [--compact] [--leaf N] [--bins N] [--cisect X] [--split R] [--split-depth N]
//   [--options "CL build options"]
// Returns the process exit code (0 ok, 1 bad arguments / mismatch with Embree, 3 device).
int bench_main(const std::vector<std::string>& args, const SceneSource& source = {});

}  // namespace ht
