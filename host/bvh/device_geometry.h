// Scene geometry on the OpenCL device and a tracer for host ray arrays (tests, bench).
#pragma once

#include "bvh/bvh.h"
#include "cl/device.h"
#include "bvh/geometry_paging.h"
#include "bvh/path_grid_buffers.h"
#include "core/bulk_vector.h"

#include <string>
#include <functional>
#include <vector>

namespace ht {

// Each array holds paging.pages buffers, in kernel-argument order (kernels/geometry/pages.h).
struct DeviceGeometry {
    std::vector<cl::Buffer> nodes, segments, points;
    std::vector<cl::Buffer> triangles;  // HtTriangleShading per triangle (one dummy element when none)
    GeometryPaging paging;
    size_t triangle_count = 0;  // decides HT_FEATURE_MESHES for DeviceTracer
    size_t bytes = 0;
};

// How upload_geometry (and read_only_buffer, below, for the renderer's lists) gives the arrays to
// the device.  Copy: read-only device buffers of their own, the arrays may go when it returns.
// Shared: on a CPU device, an array (or page) of 2 MiB or more that starts on a 2 MiB boundary
// (SceneGeometry's BulkVectors do) is the buffer itself (CL_MEM_USE_HOST_PTR): no copy, no second
// set of pages to fault in (the anchor's head: 115 MB, ~30,000 faults), half the memory; the
// arrays must then outlive the DeviceGeometry unchanged.  Elsewhere, Shared copies.
enum class GeometryMemory { Copy, Shared };

// One array of `bytes` at `data` as a read-only device buffer, given as `memory` says (Shared: the
// array itself where it qualifies, so it must outlive the buffer unchanged); `what` names it in
// the DeviceError thrown when the device refuses it.  An empty array gets a 16-byte buffer.
cl::Buffer read_only_buffer(ClContext& cl, const std::string& what, const void* data, size_t bytes,
                            GeometryMemory memory);

// The arrays as read-only device buffers, paged (plan_geometry_pages) when one exceeds max_alloc
// (0: the device's maximum allocation, which HAIRTRACE_MAX_ALLOC may lower).  Throws DeviceError
// naming the array and the sizes when even kMaxGeometryPages pages are too few.
DeviceGeometry upload_geometry(ClContext& cl, const SceneGeometry& geo, uint64_t max_alloc = 0,
                               GeometryMemory memory = GeometryMemory::Copy);

// Sets one paged array's kernel arguments from index `arg` on; returns the next free index.
cl_uint set_paged_args(cl::Kernel& k, cl_uint arg, const std::vector<cl::Buffer>& pages);

// " -DHT_GEOMETRY_PAGES=K [-DHT_GEOMETRY_PAGE_LOG2=S]": what programs indexing this geometry are
// built with.
std::string geometry_page_options(const GeometryPaging& paging);

// Owns a program with the intersect_closest / intersect_shadow stages (kernels/stages/
// intersect.cl) and traces ray arrays against one uploaded geometry.  Ray and result buffers
// are kept between calls and grown when needed.  Unless `options` says otherwise, the program
// is built with HT_FEATURE_MESHES = (the geometry has triangles), so hair-only geometry runs
// the pure capsule leaf loop.
class DeviceTracer {
public:
    static constexpr size_t kLocalSize = 64;  // docs/POCL.md §1: 32-256 equal, must be explicit

    DeviceTracer(ClContext& cl, const DeviceGeometry& geo,
                 const std::string& options = default_options());

    // The render program's own options (host/cl/device.h), so that what `hairtrace bench`
    // measures is the traversal the renderer runs; HT_FEATURE_MESHES and the paging options are
    // added from the geometry exactly as the renderer adds them.
    static std::string default_options() { return base_kernel_options(); }

    // The options the program was built with (all of them).
    const std::string& options() const { return options_; }

    // Build time of the program (ms) and whether it came from the binary cache.
    double build_ms() const { return build_ms_; }
    bool build_cached() const { return build_cached_; }

    // Uploads rays (tmax = +inf replaced by a large finite value) for the trace calls below.
    void set_rays(const std::vector<HtRay>& rays);
    // Where each uploaded ray's closest-hit traversal starts (host/bvh/start_nodes.h), one
    // inner node reference per ray (0: the root); until then, and after set_rays, the root.
    void set_starts(const std::vector<uint32_t>& starts);
    // The path rays' grid (render/path_grid.h: its cell starts, entries and cells): from then on,
    // until set_rays or use_tree, enqueue_closest traces the uploaded rays by it (the renderer's own
    // intersect_closest_paths with HT_FEATURE_PATH_GRID) instead of the tree, and enqueue_shadow,
    // without shadow lists, answers them by it (the renderer's intersect_shadow with the feature).
    void set_path_grid(const BulkVector<uint32_t>& cell_start, const BulkVector<uint32_t>& entries,
                       const HtPathGrid& grid);
    void use_path_grid();
    // The lights' shadow lists (render/shadow_lists.h: grids, cell starts and counts, entries and
    // keys): from then on, until set_rays or use_tree, enqueue_shadow answers the uploaded rays by them (the
    // renderer's own intersect_shadow_lists; rays no grid serves traverse the tree there).
    void set_shadow_lists(const std::vector<HtShadowGrid>& grids, const std::vector<uint32_t>& start,
                          const std::vector<uint32_t>& count, const BulkVector<uint32_t>& primitive,
                          const BulkVector<float>& key);
    void use_shadow_lists();
    // Back to the tree for both kinds of rays (the structures given stay, for use_* again).
    void use_tree();
    // A camera's per-pixel candidate lists (render/candidate_lists.h: starts, counts, entries and
    // depths, the depth row, each entry's node) and the pixel of each uploaded ray: from then on,
    // until set_rays or use_tree, enqueue_closest traces the uploaded rays as the render's camera stage does
    // (kernels/stages/intersect_camera.cl; a pixel whose list was capped traverses the tree).
    void set_camera_lists(const std::vector<uint32_t>& start, const std::vector<uint32_t>& count,
                          const BulkVector<uint32_t>& primitive, const BulkVector<float>& depth, const float depth_row[3],
                          const std::vector<uint32_t>& leaf_node, const std::vector<uint32_t>& ray_pixels);
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
    void build_lists_program();
    // k's arguments: the geometry, the rays, `out`, the count, then extra(k, next index)'s
    // (work_items: the launch's work-items before rounding to the local size, 0 for one per ray)
    void enqueue(cl::Kernel& k, cl::Buffer& out, const std::function<void(cl::Kernel&, cl_uint)>& extra = {},
                 size_t work_items = 0);

    ClContext& cl_;
    const DeviceGeometry& geo_;
    cl::Program program_, lists_program_;  // the list stages' program: built on first use
    cl::Kernel closest_, closest_from_, closest_grid_, shadow_, shadow_grid_, shadow_lists_, camera_;
    cl::Buffer camera_start_, camera_count_, camera_primitive_, camera_depth_, camera_leaf_node_, camera_paths_,
        camera_ray_path_;
    cl_float4 camera_depth_row_{};
    PathGridBuffers path_grid_;  // as the renderer sets it (render/renderer.cpp)
    cl::Buffer list_grids_, list_start_, list_count_, list_primitive_, list_key_;
    cl_uint list_grid_count_ = 0;
    bool shadow_by_lists_ = false;
    cl::Buffer rays_, hits_, occluded_, starts_;
    enum class Closest { Root, Starts, Grid, CameraLists } closest_mode_ = Closest::Root;
    size_t capacity_ = 0, count_ = 0;
    double build_ms_ = 0;
    bool build_cached_ = false;
    std::string options_;
};

}  // namespace ht
