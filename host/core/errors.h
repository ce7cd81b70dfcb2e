// Which exception means which exit code.  Every command throws one of these (or lets a library
// exception through); main() and the MPI abort path turn it into the process exit code with
// exit_code_for(), so the mapping below is the only one.
//
//   exit 2, bad input or usage (the message names the option or file and the problem):
//     UsageError   a command-line option, value or combination of them
//     SceneError   an input file: scene, texture, checkpoint, partial image, reference image, ray file
//   exit 3, device or runtime failure:
//     DeviceError  no OpenCL platform/device, kernel build failure, device memory
//     ImageError   writing an output image or a checkpoint
//     anything else (cl::Error, std::bad_alloc, ...)
#pragma once

#include <exception>
#include <stdexcept>

namespace ht {

constexpr int kExitOk = 0, kExitUsage = 2, kExitRuntime = 3;

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct SceneError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct DeviceError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct ImageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

inline int exit_code_for(const std::exception& e) {
    if (dynamic_cast<const UsageError*>(&e) || dynamic_cast<const SceneError*>(&e)) return kExitUsage;
    return kExitRuntime;
}

}  // namespace ht
