// Scene geometry on the OpenCL device and a tracer for host ray arrays (tests, bench).
#pragma once

#include "bvh/bvh.h"
#include "cl/device.h"

#include <vector>

namespace ht {

struct DeviceGeometry {
    cl::Buffer nodes, segments, points;
    cl::Buffer triangles;       // HtTriangleShading per triangle (one dummy element when none)
    size_t triangle_count = 0;  // decides HT_FEATURE_MESHES for DeviceTracer
    size_t bytes = 0;
};

// Copies the three arrays into read-only device buffers.  Throws DeviceError naming the array
// and its size when one exceeds the device's maximum allocation.
DeviceGeometry upload_geometry(ClContext& cl, const SceneGeometry& geo);

// Owns a program with the intersect_closest / intersect_shadow stages (kernels/stages/
// intersect.cl) and traces ray arrays against one uploaded geometry.  Ray and result buffers
// are kept between calls and grown when needed.  Unless `options` says otherwise, the program
// is built with HT_FEATURE_MESHES = (the geometry has triangles), so hair-only geometry runs
// the pure capsule leaf loop.
class DeviceTracer {
public:
    static constexpr size_t kLocalSize = 64;  // POCL_FINDINGS: 32-256 equal, must be explicit

    DeviceTracer(ClContext& cl, const DeviceGeometry& geo,
                 const std::string& options = default_options());

    static std::string default_options() { return "-cl-std=CL1.2 -cl-fast-relaxed-math"; }

    // Build time of the program (ms) and whether it came from the binary cache.
    double build_ms() const { return build_ms_; }
    bool build_cached() const { return build_cached_; }

    // Uploads rays (tmax = +inf replaced by a large finite value) for the trace calls below.
    void set_rays(const std::vector<HtRay>& rays);
    // Trace the uploaded rays; the *_enqueue forms do not wait (time them with finish()).
    void enqueue_closest();
    void enqueue_shadow();
    void finish();
    void read_hits(std::vector<HtHit>& hits);
    void read_occluded(std::vector<uint32_t>& occluded);

    // Convenience: upload + trace + read back.
    std::vector<HtHit> trace_closest(const std::vector<HtRay>& rays);
    std::vector<uint32_t> trace_shadow(const std::vector<HtRay>& rays);

private:
    void enqueue(cl::Kernel& k, cl::Buffer& out);

    ClContext& cl_;
    const DeviceGeometry& geo_;
    cl::Program program_;
    cl::Kernel closest_, shadow_;
    cl::Buffer rays_, hits_, occluded_;
    size_t capacity_ = 0, count_ = 0;
    double build_ms_ = 0;
    bool build_cached_ = false;
};

}  // namespace ht
