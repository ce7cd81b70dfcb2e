#include "bvh/device_geometry.h"

#include <cmath>
#include <cstdio>

namespace ht {

namespace {
// Runtime failures of the tracer as DeviceError naming the step (cl::Error only has a code).
template <typename F> void device_step(const char* what, F&& f) {
    try {
        f();
    } catch (const cl::Error& e) {
        throw DeviceError(std::string("intersection: ") + what + " failed: " + e.what() + " (" +
                          cl_error_name(e.err()) + ")");
    }
}
}  // namespace

namespace {
cl::Buffer make_buffer(ClContext& cl, const char* what, const void* data, size_t bytes) {
    const unsigned long long max_alloc = cl.info().max_alloc;
    if (max_alloc && bytes > max_alloc) {
        char msg[256];
        std::snprintf(msg, sizeof msg,
                      "the scene's %s array needs %.1f MiB but the device %s allocates at most "
                      "%.1f MiB per buffer; use a smaller scene or another device",
                      what, bytes / 1048576.0, cl.info().name.c_str(), max_alloc / 1048576.0);
        throw DeviceError(msg);
    }
    // A zero-sized buffer is invalid in OpenCL; an empty array still gets one element.
    const size_t n = bytes ? bytes : 16;
    try {
        if (!bytes) return cl::Buffer(cl.context(), CL_MEM_READ_ONLY, n);
        return cl::Buffer(cl.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n,
                          const_cast<void*>(data));
    } catch (const cl::Error& e) {
        throw DeviceError(std::string("cannot allocate the ") + what + " buffer (" +
                          std::to_string(bytes) + " bytes) on " + cl.info().name + ": " +
                          cl_error_name(e.err()));
    }
}
}  // namespace

DeviceGeometry upload_geometry(ClContext& cl, const SceneGeometry& geo) {
    DeviceGeometry d;
    const size_t nb = geo.nodes.size() * sizeof(HtBvhNode);
    const size_t sb = geo.segments.size() * sizeof(HtSegment);
    const size_t pb = geo.points.size() * sizeof(HtPoint);
    d.nodes = make_buffer(cl, "BVH node", geo.nodes.data(), nb);
    d.segments = make_buffer(cl, "segment", geo.segments.data(), sb);
    d.points = make_buffer(cl, "point", geo.points.data(), pb);
    const size_t tb = geo.triangles.size() * sizeof(HtTriangleShading);
    d.triangles = make_buffer(cl, "triangle shading", geo.triangles.data(), tb);
    d.triangle_count = geo.triangles.size();
    d.bytes = nb + sb + pb + tb;
    return d;
}

DeviceTracer::DeviceTracer(ClContext& cl, const DeviceGeometry& geo, const std::string& options)
    : cl_(cl), geo_(geo) {
    std::string opts = options;
    if (opts.find("HT_FEATURE_MESHES") == std::string::npos)
        opts += geo.triangle_count ? " -DHT_FEATURE_MESHES=1" : " -DHT_FEATURE_MESHES=0";
    program_ = cl.build("stages/intersect.cl", opts);  // throws DeviceError with the log
    build_ms_ = cl.last_build_ms();
    build_cached_ = cl.last_build_cached();
    device_step("creating the intersection kernels", [&] {
        closest_ = cl::Kernel(program_, "intersect_closest");
        shadow_ = cl::Kernel(program_, "intersect_shadow");
    });
}


void DeviceTracer::set_rays(const std::vector<HtRay>& rays) {
    count_ = rays.size();
    if (count_ > capacity_) {
        const size_t bytes = count_ * sizeof(HtHit);
        if (cl_.info().max_alloc && bytes > cl_.info().max_alloc)
            throw DeviceError("intersection: " + std::to_string(count_) + " rays need a " +
                              std::to_string(bytes >> 20) + " MiB hit buffer, more than the "
                              "device's maximum allocation; trace them in smaller batches");
        device_step("allocating ray/hit buffers", [&] {
            capacity_ = count_;
            rays_ = cl::Buffer(cl_.context(), CL_MEM_READ_ONLY, capacity_ * sizeof(HtRay));
            hits_ = cl::Buffer(cl_.context(), CL_MEM_WRITE_ONLY, capacity_ * sizeof(HtHit));
            occluded_ = cl::Buffer(cl_.context(), CL_MEM_WRITE_ONLY, capacity_ * sizeof(uint32_t));
        });
    }
    if (!count_) return;
    // The kernels clamp tmax too; replacing inf here keeps it out of the device entirely
    // (-cl-fast-relaxed-math assumes finite values).
    std::vector<HtRay> clean(rays);
    for (HtRay& r : clean)
        if (!(r.tmax <= 3.0e38f)) r.tmax = 3.0e38f;
    device_step("uploading rays", [&] {
        cl_.queue().enqueueWriteBuffer(rays_, CL_TRUE, 0, count_ * sizeof(HtRay), clean.data());
    });
}

void DeviceTracer::enqueue(cl::Kernel& k, cl::Buffer& out) {
    if (!count_) return;
    device_step("kernel launch", [&] {
        k.setArg(0, geo_.nodes);
        k.setArg(1, geo_.segments);
        k.setArg(2, geo_.points);
        k.setArg(3, rays_);
        k.setArg(4, out);
        k.setArg(5, (cl_uint)count_);
        cl_.queue().enqueueNDRangeKernel(k, cl::NullRange,
                                         cl::NDRange(round_up(count_, kLocalSize)),
                                         cl::NDRange(kLocalSize));
    });
}

void DeviceTracer::enqueue_closest() { enqueue(closest_, hits_); }
void DeviceTracer::enqueue_shadow() { enqueue(shadow_, occluded_); }
void DeviceTracer::finish() {
    device_step("kernel execution", [&] { cl_.queue().finish(); });
}

void DeviceTracer::read_hits(std::vector<HtHit>& hits) {
    hits.resize(count_);
    if (count_)
        device_step("reading hits", [&] {
            cl_.queue().enqueueReadBuffer(hits_, CL_TRUE, 0, count_ * sizeof(HtHit), hits.data());
        });
}

void DeviceTracer::read_occluded(std::vector<uint32_t>& occ) {
    occ.resize(count_);
    if (count_)
        device_step("reading occlusion flags", [&] {
            cl_.queue().enqueueReadBuffer(occluded_, CL_TRUE, 0, count_ * sizeof(uint32_t),
                                          occ.data());
        });
}

std::vector<HtHit> DeviceTracer::trace_closest(const std::vector<HtRay>& rays) {
    set_rays(rays);
    enqueue_closest();
    std::vector<HtHit> hits;
    read_hits(hits);
    return hits;
}

std::vector<uint32_t> DeviceTracer::trace_shadow(const std::vector<HtRay>& rays) {
    set_rays(rays);
    enqueue_shadow();
    std::vector<uint32_t> occ;
    read_occluded(occ);
    return occ;
}

}  // namespace ht
