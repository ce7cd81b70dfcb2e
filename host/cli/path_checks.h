// The checks every path on the command line passes before any work starts: an input exists; an
// output names a format this build writes and lies in an existing folder we can write to.  A
// mistake found here costs nothing; found after an hour of rendering, it costs the hour.
#pragma once

#include "cli/args.h"

#include <string>

namespace ht {

// Throws UsageError starting with `what` (e.g. "render: -o") naming the path and the problem.
void check_path(const std::string& what, const std::string& path, PathKind kind);

}  // namespace ht
