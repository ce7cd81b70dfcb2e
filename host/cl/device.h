// OpenCL platforms, devices, one context + in-order queue, and program builds through a
// persistent binary cache.
#pragma once

#include "core/errors.h"

#include <CL/opencl.hpp>

#include <atomic>
#include <future>
#include <map>
#include <mutex>
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

// A finished program build: the program, its wall milliseconds and whether the binary cache
// supplied it.
struct ProgramBuild {
    cl::Program program;
    double ms = 0;
    bool cached = false;
};

class ClContext {
public:
    // device_index < 0: the first CPU or GPU device found.
    explicit ClContext(int device_index = -1);

    cl::Context& context() { return context_; }
    cl::CommandQueue& queue() { return queue_; }
    cl::Device& device() { return device_; }
    const DeviceInfo& info() const { return info_; }

    // Builds kernels/<main_file> (assembled with #line markers) with the options its source reads
    // (options_read_by, cl/kernel_source.h), through the binary cache.  Throws DeviceError with the build log on failure.
    // A build that prefetch() started with the same file and options is waited for instead.
    cl::Program build(const std::string& main_file, const std::string& options);

    // Starts the same build on a background thread and returns at once, so that the compile
    // (seconds with a cold cache) overlaps host work such as the BVH build.  Its failure is
    // reported by the build() that collects it; a prefetch nobody collects is waited for and
    // dropped with the context.
    void prefetch(const std::string& main_file, const std::string& options);

    // Waits for every prefetch no build() has collected and discards it.  Whoever started one and
    // then failed calls this, so the wait happens while the process runs: a context that lives in
    // a static is otherwise destroyed after PoCL's own teardown at exit, with its compile still
    // running, and the process crashed there (tests/render/program_build_test.cpp).
    void drop_prefetches();
    // Prefetches started and not yet collected or dropped.
    size_t pending_prefetches();

    // Programs this context has compiled or loaded from the cache, prefetched ones included
    // (a prefetch that build() collects counts once).
    int compiles() const { return compiles_; }

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
    std::atomic<int> compiles_{0};
    std::mutex prefetch_mutex_;
    // Declared last: destroyed first, so a running prefetch finishes while the context lives.
    std::map<std::string, std::future<ProgramBuild>> prefetched_;  // by file + options

    ProgramBuild compile(const std::string& main_file, const std::string& options);
};

// Build options every hairtrace program uses.  -cl-single-precision-constant: portable headers
// write literals without an f suffix (they are double on the host), and a double constant would
// otherwise promote float math to double on devices with fp64 (slow) and warn on devices without.
// -cl-fast-relaxed-math is deliberately absent: it implies finite-math-only, under which the
// compiler may delete the NaN/Inf guards the fibre models rely on.
// -cl-denorms-are-zero: the fibre models make denormals on their hot path (e^{-2/v} underflows
// for v < 0.023, which chiang's TT lobe has at beta_m = 0.3, and far-off-peak M_p values), and
// x86 handles each one in microcode, ~100 cycles; PoCL then runs the kernels with FTZ/DAZ set.
// Nothing in the kernels depends on a denormal (guards use the smallest normal float); the images
// measured are identical to the bit, and the shade stage ~14 % faster on pbrt's lock
// (docs/PERFORMANCE.md section 3, "Denormals flushed").
inline const char* base_kernel_options() {
    return "-cl-std=CL1.2 -cl-mad-enable -cl-single-precision-constant -cl-denorms-are-zero";
}

// Rounds n up to a multiple of m.
inline size_t round_up(size_t n, size_t m) { return (n + m - 1) / m * m; }

}  // namespace ht
