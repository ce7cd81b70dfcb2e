#include "bvh/device_geometry.h"

#include "kernels/geometry/candidate_list.h"
#include "kernels/geometry/pages.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>

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

cl::Buffer read_only_buffer(ClContext& cl, const std::string& what, const void* data, size_t bytes,
                            GeometryMemory memory) {
    // A zero-sized buffer is invalid in OpenCL; an empty array still gets one element.
    const size_t n = bytes ? bytes : 16;
    constexpr size_t kHugePage = BulkAllocator<unsigned char>::kHugePage;
    const bool shared = memory == GeometryMemory::Shared && cl.info().type == "CPU" && bytes >= kHugePage &&
                        reinterpret_cast<uintptr_t>(data) % kHugePage == 0;
    try {
        if (!bytes) return cl::Buffer(cl.context(), CL_MEM_READ_ONLY, n);
        return cl::Buffer(cl.context(), CL_MEM_READ_ONLY | (shared ? CL_MEM_USE_HOST_PTR : CL_MEM_COPY_HOST_PTR), n,
                          const_cast<void*>(data));
    } catch (const cl::Error& e) {
        throw DeviceError(std::string("cannot allocate the ") + what + " buffer (" +
                          std::to_string(bytes) + " bytes) on " + cl.info().name + ": " +
                          cl_error_name(e.err()));
    }
}

namespace {
static_assert(kMaxGeometryPages == HT_MAX_GEOMETRY_PAGES, "one page limit for host and kernels");

// The array as paging.pages buffers; pages past its end repeat its last buffer (never read:
// no index reaches them, but every kernel argument must be a valid buffer).
template <typename T, typename Allocator>
std::vector<cl::Buffer> make_pages(ClContext& cl, const char* what, const std::vector<T, Allocator>& v,
                                   const GeometryPaging& paging, GeometryMemory memory) {
    const size_t bytes = v.size() * sizeof(T);
    if (paging.pages == 1) return {read_only_buffer(cl, what, v.data(), bytes, memory)};
    const size_t per_page = size_t(paging.page_bytes() / sizeof(T));
    std::vector<cl::Buffer> out;
    for (size_t first = 0; first < v.size() || out.empty(); first += per_page) {
        const size_t n = std::min(per_page, v.size() - first);
        out.push_back(read_only_buffer(cl, std::string(what) + " page " + std::to_string(out.size()),
                                  v.data() + first, n * sizeof(T), memory));
    }
    while (out.size() < paging.pages) out.push_back(out.back());
    return out;
}
}  // namespace

DeviceGeometry upload_geometry(ClContext& cl, const SceneGeometry& geo, uint64_t max_alloc, GeometryMemory memory) {
    DeviceGeometry d;
    const size_t nb = geo.nodes.size() * sizeof(HtBvhNode);
    const size_t sb = geo.segments.size() * sizeof(HtSegment);
    const size_t pb = geo.points.size() * sizeof(HtPoint);
    const size_t tb = geo.triangles.size() * sizeof(HtTriangleShading);
    try {
        d.paging = plan_geometry_pages({{"BVH node", nb}, {"segment", sb}, {"point", pb}, {"triangle shading", tb}},
                                       max_alloc ? max_alloc : cl.info().max_alloc);
    } catch (const DeviceError& e) {
        throw DeviceError(std::string(e.what()) + " (device: " + cl.info().name + ")");
    }
    d.nodes = make_pages(cl, "BVH node", geo.nodes, d.paging, memory);
    d.segments = make_pages(cl, "segment", geo.segments, d.paging, memory);
    d.points = make_pages(cl, "point", geo.points, d.paging, memory);
    d.triangles = make_pages(cl, "triangle shading", geo.triangles, d.paging, memory);
    d.triangle_count = geo.triangles.size();
    d.bytes = nb + sb + pb + tb;
    return d;
}

cl_uint set_paged_args(cl::Kernel& k, cl_uint arg, const std::vector<cl::Buffer>& pages) {
    for (const cl::Buffer& b : pages) k.setArg(arg++, b);
    return arg;
}

std::string geometry_page_options(const GeometryPaging& paging) {
    std::string o = " -DHT_GEOMETRY_PAGES=" + std::to_string(paging.pages);
    if (paging.pages > 1) o += " -DHT_GEOMETRY_PAGE_LOG2=" + std::to_string(paging.page_log2);
    return o;
}

namespace {
// One host array as a read-only buffer of the tracer's own (a copy: the caller's arrays may go).
template <typename Array>
cl::Buffer copied(ClContext& cl, const char* what, const Array& a) {
    return read_only_buffer(cl, what, a.data(), a.size() * sizeof(a[0]), GeometryMemory::Copy);
}
// Kernel arguments from index `a` on, in order; returns the next free index.
template <typename... Args>
cl_uint set_args(cl::Kernel& k, cl_uint a, const Args&... args) {
    (k.setArg(a++, args), ...);
    return a;
}
}  // namespace

DeviceTracer::DeviceTracer(ClContext& cl, const DeviceGeometry& geo, const std::string& options)
    : cl_(cl), geo_(geo) {
    std::string opts = options;
    if (opts.find("HT_FEATURE_MESHES") == std::string::npos)
        opts += geo.triangle_count ? " -DHT_FEATURE_MESHES=1" : " -DHT_FEATURE_MESHES=0";
    if (opts.find("HT_FEATURE_PATH_GRID") == std::string::npos) opts += " -DHT_FEATURE_PATH_GRID=1";
    opts += geometry_page_options(geo.paging);
    options_ = opts;
    program_ = cl.build("stages/intersect.cl", opts);  // throws DeviceError with the log
    build_ms_ = cl.last_build_ms();
    build_cached_ = cl.last_build_cached();
    device_step("creating the intersection kernels", [&] {
        closest_ = cl::Kernel(program_, "intersect_closest");
        closest_from_ = cl::Kernel(program_, "intersect_closest_from");
        closest_grid_ = cl::Kernel(program_, "intersect_closest_paths");
        // the tree's any hit; with the grid compiled in, intersect_shadow walks the grid
        const bool grid = options_.find("HT_FEATURE_PATH_GRID=1") != std::string::npos;
        shadow_ = cl::Kernel(program_, grid ? "intersect_shadow_tree" : "intersect_shadow");
        if (grid) shadow_grid_ = cl::Kernel(program_, "intersect_shadow");
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
            starts_ = cl::Buffer(cl_.context(), CL_MEM_READ_ONLY, capacity_ * sizeof(uint32_t));
        });
    }
    closest_mode_ = Closest::Root;
    shadow_by_lists_ = false;
    if (!count_) return;
    // The kernels clamp tmax too; replacing inf here keeps it out of the device entirely (a
    // program built with -cl-fast-relaxed-math through `bench --options` assumes finite values).
    std::vector<HtRay> clean(rays);
    for (HtRay& r : clean)
        if (!(r.tmax <= 3.0e38f)) r.tmax = 3.0e38f;
    device_step("uploading rays", [&] {
        cl_.queue().enqueueWriteBuffer(rays_, CL_TRUE, 0, count_ * sizeof(HtRay), clean.data());
    });
}

void DeviceTracer::set_starts(const std::vector<uint32_t>& starts) {
    if (starts.size() != count_)
        throw std::invalid_argument("DeviceTracer::set_starts: " + std::to_string(starts.size()) + " start nodes for " +
                                    std::to_string(count_) + " rays");
    if (count_)
        device_step("uploading start nodes", [&] {
            cl_.queue().enqueueWriteBuffer(starts_, CL_TRUE, 0, count_ * sizeof(uint32_t), starts.data());
        });
    closest_mode_ = Closest::Starts;
}

void DeviceTracer::set_path_grid(const BulkVector<uint32_t>& cell_start, const BulkVector<uint32_t>& entries,
                                 const HtPathGrid& grid) {
    path_grid_.cells = copied(cl_, "path grid cells", cell_start);
    path_grid_.entries = copied(cl_, "path grid entries", entries);
    path_grid_.grid = grid;
}

void DeviceTracer::use_path_grid() {
    if (!path_grid_.cells()) throw std::logic_error("DeviceTracer::use_path_grid before set_path_grid");
    closest_mode_ = Closest::Grid;
}

void DeviceTracer::build_lists_program() {
    if (lists_program_()) return;
    // the render's list stages (kernels/stages/lists.cl), built with the tracer's options when a
    // caller first gives lists: PoCL compiles every kernel of a program, ~0.8 s each when cold
    lists_program_ = cl_.build("stages/lists.cl", options_);
    device_step("creating the list stages' kernels", [&] {
        shadow_lists_ = cl::Kernel(lists_program_, "intersect_shadow_lists");
        camera_ = cl::Kernel(lists_program_, "intersect_camera");
    });
}

void DeviceTracer::set_shadow_lists(const std::vector<HtShadowGrid>& grids, const std::vector<uint32_t>& start,
                                    const std::vector<uint32_t>& count, const BulkVector<uint32_t>& primitive,
                                    const BulkVector<float>& key) {
    list_grids_ = copied(cl_, "shadow list grids", grids);
    list_start_ = copied(cl_, "shadow list starts", start);
    list_count_ = copied(cl_, "shadow list counts", count);
    list_primitive_ = copied(cl_, "shadow list primitives", primitive);
    list_key_ = copied(cl_, "shadow list keys", key);
    list_grid_count_ = cl_uint(grids.size());
    build_lists_program();
}

void DeviceTracer::set_camera_lists(const std::vector<uint32_t>& start, const std::vector<uint32_t>& count,
                                    const BulkVector<uint32_t>& primitive, const BulkVector<float>& depth,
                                    const float depth_row[3], const std::vector<uint32_t>& leaf_node,
                                    const std::vector<uint32_t>& ray_pixels) {
    if (ray_pixels.size() != count_)
        throw std::invalid_argument("DeviceTracer::set_camera_lists: " + std::to_string(ray_pixels.size()) + " pixels for " +
                                    std::to_string(count_) + " rays");
    camera_start_ = copied(cl_, "camera list starts", start);
    camera_count_ = copied(cl_, "camera list counts", count);
    camera_primitive_ = copied(cl_, "camera list primitives", primitive);
    camera_depth_ = copied(cl_, "camera list depths", depth);
    camera_leaf_node_ = copied(cl_, "camera list nodes", leaf_node);
    camera_depth_row_ = cl_float4{{depth_row[0], depth_row[1], depth_row[2], 0.0f}};
    // ray i is path i's, whose state names its pixel (the stage writes the hit's node back there)
    std::vector<HtPathState> paths(std::max<size_t>(1, count_));
    std::vector<uint32_t> ray_path(count_);
    for (size_t i = 0; i < count_; ++i) paths[i].pixel = ray_pixels[i], ray_path[i] = uint32_t(i);
    device_step("uploading the camera rays' paths", [&] {
        camera_paths_ = cl::Buffer(cl_.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                                   paths.size() * sizeof(HtPathState), paths.data());
    });
    camera_ray_path_ = copied(cl_, "camera ray paths", ray_path);
    build_lists_program();
    closest_mode_ = Closest::CameraLists;
}

void DeviceTracer::use_tree() {
    closest_mode_ = Closest::Root;
    shadow_by_lists_ = false;
}

void DeviceTracer::use_shadow_lists() {
    if (!list_grids_()) throw std::logic_error("DeviceTracer::use_shadow_lists before set_shadow_lists");
    shadow_by_lists_ = true;
}

void DeviceTracer::enqueue(cl::Kernel& k, cl::Buffer& out, const std::function<void(cl::Kernel&, cl_uint)>& extra,
                           size_t work_items) {
    if (!count_) return;
    device_step("kernel launch", [&] {
        cl_uint a = set_paged_args(k, 0, geo_.nodes);
        a = set_paged_args(k, a, geo_.segments);
        a = set_paged_args(k, a, geo_.points);
        k.setArg(a++, rays_);
        k.setArg(a++, out);
        k.setArg(a++, (cl_uint)count_);
        if (extra) extra(k, a);
        const size_t items = work_items ? work_items : count_;
        cl_.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(round_up(items, kLocalSize)), cl::NDRange(kLocalSize));
    });
}

void DeviceTracer::enqueue_closest() {
    switch (closest_mode_) {
    case Closest::Root: enqueue(closest_, hits_); break;
    case Closest::Starts: enqueue(closest_from_, hits_, [&](cl::Kernel& k, cl_uint a) { k.setArg(a, starts_); }); break;
    case Closest::Grid:
        // the path stage's arguments: ray i of path ray_path[i] in paths, which its grid variant
        // reads neither of (any buffers do), then the grid
        enqueue(closest_grid_, hits_, [&](cl::Kernel& k, cl_uint a) {
            set_bundle_args(k, set_args(k, a, starts_, occluded_), path_grid_);
        });
        break;
    case Closest::CameraLists:  // intersect_camera.cl's order
        enqueue(camera_, hits_, [&](cl::Kernel& k, cl_uint a) {
            set_args(k, a, camera_ray_path_, camera_paths_, camera_start_, camera_count_, camera_primitive_, camera_depth_,
                     camera_depth_row_, camera_leaf_node_);
        });
        break;
    }
}
void DeviceTracer::enqueue_shadow() {
    // the render's stage by the grid (none in a program built with HT_FEATURE_PATH_GRID=0: the tree)
    if (!shadow_by_lists_ && closest_mode_ == Closest::Grid && shadow_grid_()) {
        enqueue(shadow_grid_, occluded_, [&](cl::Kernel& k, cl_uint a) { set_bundle_args(k, a, path_grid_); });
        return;
    }
    if (!shadow_by_lists_) {
        enqueue(shadow_, occluded_);
        return;
    }
    // intersect_shadow_lists.cl's order; several rays per work-item (kernels/geometry/candidate_list.h)
    enqueue(
        shadow_lists_, occluded_,
        [&](cl::Kernel& k, cl_uint a) {
            set_args(k, a, list_grid_count_, list_grids_, list_start_, list_count_, list_primitive_, list_key_);
        },
        ht_shadow_list_items(cl_uint(count_)));
}
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
