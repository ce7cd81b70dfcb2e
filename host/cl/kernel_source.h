// Kernel source text: embedded at build time, or read from a kernels/ folder in development
// (HAIRTRACE_KERNEL_DIR or --kernel-dir), assembled into one string with #line markers.
#pragma once

#include <string>

namespace ht {

// Where kernel files come from.  Empty = the copies embedded in the binary.
void set_kernel_dir(const std::string& dir);
const std::string& kernel_dir();

// Text of one kernel file (path relative to kernels/, e.g. "stages/shade.cl").  Throws
// std::runtime_error naming the file when it does not exist.
std::string kernel_file(const std::string& rel_path);

// main_file with every #include "x" inlined once (include guards still apply) and a #line
// marker before and after each inlined file, so compiler messages name kernels/<file>:<line>.
std::string assemble_kernel_source(const std::string& main_file);

}  // namespace ht
