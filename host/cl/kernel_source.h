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

// `options` without the -DNAME[=value] tokens that `source` does not read: NAME occurs nowhere
// but in its own default declaration (#ifndef NAME / #define NAME).  Programs built from
// different stages then share a build (and a cache entry) across scenes that differ only in
// what another stage reads; a dropped define cannot change the program.
std::string options_read_by(const std::string& source, const std::string& options);

}  // namespace ht
