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

// args = the command line after "bench" (`hairtrace bench --help` lists the options).  Returns
// the process exit code (0 ok, 1 hits disagree with a ray file); usage errors throw UsageError.
int bench_main(const std::vector<std::string>& args, const SceneSource& source = {});

}  // namespace ht
