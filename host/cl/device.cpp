#include "cl/device.h"

#include "cl/kernel_source.h"
#include "core/byte_size.h"
#include "core/cache_dir.h"
#include "core/errors.h"
#include "core/hash.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace ht {
namespace fs = std::filesystem;

std::string cl_error_name(int err) {
    switch (err) {
    case CL_DEVICE_NOT_FOUND: return "CL_DEVICE_NOT_FOUND";
    case CL_DEVICE_NOT_AVAILABLE: return "CL_DEVICE_NOT_AVAILABLE";
    case CL_COMPILER_NOT_AVAILABLE: return "CL_COMPILER_NOT_AVAILABLE";
    case CL_MEM_OBJECT_ALLOCATION_FAILURE: return "CL_MEM_OBJECT_ALLOCATION_FAILURE (device memory exhausted)";
    case CL_OUT_OF_RESOURCES: return "CL_OUT_OF_RESOURCES";
    case CL_OUT_OF_HOST_MEMORY: return "CL_OUT_OF_HOST_MEMORY";
    case CL_BUILD_PROGRAM_FAILURE: return "CL_BUILD_PROGRAM_FAILURE";
    case CL_INVALID_VALUE: return "CL_INVALID_VALUE";
    case CL_INVALID_BUFFER_SIZE: return "CL_INVALID_BUFFER_SIZE (larger than the device's max allocation)";
    case CL_INVALID_KERNEL_ARGS: return "CL_INVALID_KERNEL_ARGS";
    case CL_INVALID_WORK_GROUP_SIZE: return "CL_INVALID_WORK_GROUP_SIZE";
    case CL_INVALID_BUILD_OPTIONS: return "CL_INVALID_BUILD_OPTIONS";
    case CL_PLATFORM_NOT_FOUND_KHR: return "CL_PLATFORM_NOT_FOUND_KHR (no OpenCL platform installed)";
    default: return "OpenCL error " + std::to_string(err);
    }
}

namespace {
const char* kInstallHint =
    "no OpenCL platform found: install an OpenCL driver, e.g. `apt-get install pocl-opencl-icd` "
    "(CPU) or your GPU vendor's ICD";

std::string type_name(cl_device_type t) {
    if (t & CL_DEVICE_TYPE_GPU) return "GPU";
    if (t & CL_DEVICE_TYPE_CPU) return "CPU";
    if (t & CL_DEVICE_TYPE_ACCELERATOR) return "ACCELERATOR";
    return "OTHER";
}

struct Found {
    cl::Platform platform;
    cl::Device device;
    DeviceInfo info;
};

// HAIRTRACE_MAX_ALLOC=SIZE lowers every device's maximum allocation, so that the code paths of
// devices with small allocations (paged geometry, the memory planner's refusals) can be run and
// tested on a CPU device whose limit is gigabytes.
unsigned long long max_alloc_cap() {
    const char* e = std::getenv("HAIRTRACE_MAX_ALLOC");
    if (!e || !*e) return ~0ull;
    try {
        return parse_bytes(e);
    } catch (const std::exception& x) {
        throw UsageError(std::string("HAIRTRACE_MAX_ALLOC='") + e + "' is not a size like 64K, 512M or 1G (" +
                         x.what() + ")");
    }
}

// PoCL compiles each kernel twice when nothing is cached: a generic work-group function when
// the program binary is read for hairtrace's cache, and one specialised to the local size at the
// kernel's first launch.  The specialised code measured no faster for these kernels
// (docs/POCL.md §4), so PoCL is asked for the generic one only, which the cached binary then
// also carries.  Set before the first OpenCL call, when PoCL reads it; a user's value is kept.
void configure_pocl() { ::setenv("POCL_WORK_GROUP_SPECIALIZATION", "0", 0); }

// PoCL's settings that change the machine code a cached binary carries (it carries every kernel's
// compiled work-group function, above): the work-group method (loopvec, loops, cbs) and extra build
// flags.  They enter the cache key, so that a binary compiled under one is not loaded under another
// (tests/render/program_build_test.cpp).
std::string pocl_code_settings() {
    std::string text;
    for (const char* name : {"POCL_WORK_GROUP_METHOD", "POCL_EXTRA_BUILD_FLAGS"}) {
        const char* value = std::getenv(name);
        if (value && *value) text += std::string("\n") + name + "=" + value;
    }
    return text;
}

std::vector<Found> enumerate() {
    configure_pocl();
    std::vector<cl::Platform> platforms;
    try {
        cl::Platform::get(&platforms);
    } catch (const cl::Error& e) {
        throw DeviceError(kInstallHint);
    }
    if (platforms.empty()) throw DeviceError(kInstallHint);
    std::vector<Found> out;
    for (auto& p : platforms) {
        std::vector<cl::Device> devs;
        try {
            p.getDevices(CL_DEVICE_TYPE_ALL, &devs);
        } catch (const cl::Error&) {
            continue;  // a platform without devices
        }
        for (auto& d : devs) {
            Found f{p, d, {}};
            DeviceInfo& i = f.info;
            i.index = int(out.size());
            i.platform = p.getInfo<CL_PLATFORM_NAME>();
            i.platform_version = p.getInfo<CL_PLATFORM_VERSION>();
            i.name = d.getInfo<CL_DEVICE_NAME>();
            i.vendor = d.getInfo<CL_DEVICE_VENDOR>();
            i.version = d.getInfo<CL_DEVICE_VERSION>();
            i.driver = d.getInfo<CL_DRIVER_VERSION>();
            i.c_version = d.getInfo<CL_DEVICE_OPENCL_C_VERSION>();
            i.type = type_name(d.getInfo<CL_DEVICE_TYPE>());
            i.compute_units = d.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
            i.global_mem = d.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
            i.max_alloc = std::min<unsigned long long>(d.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>(), max_alloc_cap());
            i.max_work_group = d.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>();
            out.push_back(f);
        }
    }
    if (out.empty()) throw DeviceError("OpenCL platforms are installed but report no device");
    return out;
}

}  // namespace

std::vector<DeviceInfo> list_devices() {
    std::vector<DeviceInfo> out;
    for (auto& f : enumerate()) out.push_back(f.info);
    return out;
}

ClContext::ClContext(int device_index) {
    auto found = enumerate();
    const Found* pick = nullptr;
    if (device_index >= 0) {
        if (device_index >= int(found.size()))
            throw DeviceError("--device " + std::to_string(device_index) + ": there are only " +
                              std::to_string(found.size()) + " OpenCL devices (see `hairtrace devices`)");
        pick = &found[device_index];
    } else {
        for (auto& f : found)
            if (f.info.type == "GPU" || f.info.type == "CPU") { pick = &f; break; }
        if (!pick) pick = &found[0];
    }
    info_ = pick->info;
    device_ = pick->device;
    try {
        context_ = cl::Context(device_);
        queue_ = cl::CommandQueue(context_, device_);
    } catch (const cl::Error& e) {
        throw DeviceError("cannot create an OpenCL context on " + info_.name + ": " +
                          cl_error_name(e.err()));
    }
}

namespace {
std::string prefetch_key(const std::string& main_file, const std::string& options) {
    return main_file + '\n' + options;
}
}  // namespace

void ClContext::prefetch(const std::string& main_file, const std::string& options) {
    std::lock_guard<std::mutex> lock(prefetch_mutex_);
    const std::string key = prefetch_key(main_file, options);
    if (prefetched_.count(key)) return;
    prefetched_[key] = std::async(std::launch::async, [this, main_file, options] { return compile(main_file, options); });
}

void ClContext::drop_prefetches() {
    std::map<std::string, std::future<ProgramBuild>> pending;
    {
        std::lock_guard<std::mutex> lock(prefetch_mutex_);
        pending.swap(prefetched_);
    }
    for (auto& entry : pending)
        if (entry.second.valid()) entry.second.wait();  // its failure, if any, is nobody's to report
}

size_t ClContext::pending_prefetches() {
    std::lock_guard<std::mutex> lock(prefetch_mutex_);
    return prefetched_.size();
}

cl::Program ClContext::build(const std::string& main_file, const std::string& options) {
    std::future<ProgramBuild> pending;
    {
        std::lock_guard<std::mutex> lock(prefetch_mutex_);
        auto it = prefetched_.find(prefetch_key(main_file, options));
        if (it != prefetched_.end()) {
            pending = std::move(it->second);
            prefetched_.erase(it);
        }
    }
    const ProgramBuild b = pending.valid() ? pending.get() : compile(main_file, options);
    last_build_ms_ = b.ms;
    last_build_cached_ = b.cached;
    return b.program;
}

ProgramBuild ClContext::compile(const std::string& main_file, const std::string& requested_options) {
    auto t0 = std::chrono::steady_clock::now();
    ++compiles_;
    const std::string source = assemble_kernel_source(main_file);
    const std::string options = options_read_by(source, requested_options);
    const std::string key_text = source + "\n--options " + options + "\n--device " + info_.name +
                                 "\n--driver " + info_.driver + "\n--platform " +
                                 info_.platform_version + pocl_code_settings();
    std::string dir = cache_dir();  // compiled programs: one file per key
    fs::path bin_path;
    if (dir != "off") bin_path = fs::path(dir) / (hex64(fnv1a(key_text)) + ".bin");

    ProgramBuild out;
    cl::Program& program = out.program;
    bool built = false;
    if (!bin_path.empty() && fs::exists(bin_path)) {
        std::ifstream f(bin_path, std::ios::binary);
        std::vector<unsigned char> bin((std::istreambuf_iterator<char>(f)), {});
        try {
            cl::Program::Binaries bins{bin};
            program = cl::Program(context_, {device_}, bins);
            program.build({device_}, options.c_str());
            built = true;
            out.cached = true;
        } catch (const cl::Error&) {
            built = false;  // stale or foreign binary: rebuild from source below
        }
    }
    if (!built) {
        program = cl::Program(context_, source);
        try {
            program.build({device_}, options.c_str());
        } catch (const cl::Error& e) {
            std::string log;
            try {
                log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device_);
            } catch (...) {
            }
            throw DeviceError("OpenCL build of kernels/" + main_file + " failed (" +
                              cl_error_name(e.err()) + ") with options '" + options + "':\n" + log);
        }
        if (!bin_path.empty()) {
            try {
                auto bins = program.getInfo<CL_PROGRAM_BINARIES>();
                if (!bins.empty() && !bins[0].empty()) {
                    fs::create_directories(bin_path.parent_path());
                    fs::path tmp = bin_path;
                    tmp += ".tmp" + std::to_string(::getpid());
                    {
                        std::ofstream f(tmp, std::ios::binary);
                        f.write(reinterpret_cast<const char*>(bins[0].data()), bins[0].size());
                    }
                    fs::rename(tmp, bin_path);  // atomic: readers never see a partial binary
                }
            } catch (...) {
                // The cache is an optimisation; a read-only home must not fail the render.
            }
        }
    }
    out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

}  // namespace ht
