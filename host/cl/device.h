// OpenCL platforms, devices, one context + in-order queue, and program builds through a
// persistent binary cache.
#pragma once

#include "core/errors.h"

#include <CL/opencl.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace ht {

// A device or runtime failure (exit code 3).  what() says what to do about it.
struct DeviceInfo {
    int index = 0;  // global index over all platforms, as `hairtrace devices` lists it
    std::string platform, platform_version, name, vendor, version, driver, c_version;
    std::string type;  // CPU / GPU / ACCELERATOR / OTHER
    unsigned compute_units = 0;
    unsigned long long global_mem = 0, max_alloc = 0;
    size_t max_work_group = 0;
};

// All devices of all platforms.  Throws DeviceError when no platform is installed.
std::vector<DeviceInfo> list_devices();

// Human-readable message for an OpenCL error code.
std::string cl_error_name(int err);

class ClContext {
public:
    // device_index < 0: the first CPU or GPU device found.
    explicit ClContext(int device_index = -1);

    cl::Context& context() { return context_; }
    cl::CommandQueue& queue() { return queue_; }
    cl::Device& device() { return device_; }
    const DeviceInfo& info() const { return info_; }

    // Builds kernels/<main_file> (assembled with #line markers) with options, through the
    // binary cache.  Throws DeviceError with the build log on failure.
    cl::Program build(const std::string& main_file, const std::string& options);

    // Milliseconds spent in the last build() and whether it came from the cache.
    double last_build_ms() const { return last_build_ms_; }
    bool last_build_cached() const { return last_build_cached_; }

private:
    cl::Context context_;
    cl::Device device_;
    cl::CommandQueue queue_;
    DeviceInfo info_;
    double last_build_ms_ = 0;
    bool last_build_cached_ = false;
};

// Where compiled program binaries are kept: $HAIRTRACE_CACHE_DIR, else $XDG_CACHE_HOME/hairtrace,
// else ~/.cache/hairtrace.  "off" disables the cache.
std::string program_cache_dir();

// Build options every hairtrace program uses.  -cl-single-precision-constant: portable headers
// write literals without an f suffix (they are double on the host), and a double constant would
// otherwise promote float math to double on devices with fp64 (slow) and warn on devices without.
// -cl-fast-relaxed-math is deliberately absent: it implies finite-math-only, under which the
// compiler may delete the NaN/Inf guards the fibre models rely on.
inline const char* base_kernel_options() {
    return "-cl-std=CL1.2 -cl-mad-enable -cl-single-precision-constant";
}

// Rounds n up to a multiple of m.
inline size_t round_up(size_t n, size_t m) { return (n + m - 1) / m * m; }

}  // namespace ht
