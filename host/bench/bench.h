// `hairtrace bench`: BVH build and OpenCL intersection throughput, checked against the Embree
// anchor's ray files when given.
#pragma once

#include <string>
#include <vector>

namespace ht {

// args = the command line after "bench" (`hairtrace bench --help` lists the options).  Returns
// the process exit code (0 ok, 1 hits disagree with a ray file); usage errors throw UsageError.
int bench_main(const std::vector<std::string>& args);

}  // namespace ht
