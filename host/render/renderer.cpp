// The wavefront render loop.  One pass = one sample for a block of pixels; each pass runs the
// stages below until the extension queue is empty or max_depth is reached:
//
//   generate_camera_rays -> [ intersect_closest -> shade -> intersect_shadow -> resolve_shadows ]*
//                        -> accumulate
//
// With --first-hit-splits N the first shade starts N continuations per camera ray, so the queue
// of the later bounces holds up to N rays per pixel of the pass, and with
// --first-hit-light-samples M it queues M shadow rays per camera ray (render/path_buffers.h).
//
// Queue sizes come back from the device after each shade (one small read); empty queues
// launch nothing.
#include "render/renderer.h"

#include "bvh/bvh.h"
#include "bvh/device_geometry.h"
#include "cl/work_buffer.h"
#include "core/constants.h"
#include "render/environment.h"
#include "render/features.h"
#include "render/memory_plan.h"
#include "render/path_buffers.h"
#include "render/pixel_footprint.h"
#include "render/ray_dump.h"
#include "render/split_choice.h"
#include "render/stage_args.h"
#include "kernels/geometry/candidate_list.h"
#include "kernels/surface/texture.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <memory>
#include <string>
#include <cmath>
#include <cstdio>

namespace ht {

namespace {
constexpr size_t kLocalSize = kPathGroup;
// A pass renders several samples of each traced pixel (RenderSettings::samples_per_pass) only up
// to this many camera paths: beyond, one sample's launches are long enough to amortise, and the
// path buffers would grow for nothing.
constexpr size_t kSamplesPerPassPaths = size_t(1) << 18;

cl::NDRange global_for(size_t n) { return cl::NDRange(round_up(std::max<size_t>(n, 1), kLocalSize)); }

template <typename T, typename Allocator>
cl::Buffer device_array(cl::Context& ctx, const std::vector<T, Allocator>& v) {
    // OpenCL refuses zero-sized buffers; a one-element dummy keeps kernel signatures uniform.
    if (v.empty()) {
        const T dummy{};
        return cl::Buffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof(T), const_cast<T*>(&dummy));
    }
    return cl::Buffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(T), const_cast<T*>(v.data()));
}

// The render program in three builds: shade, which holds the fibre models and every scene
// feature (most of the compile); the stages around it, which read few features and so are shared
// by most scenes (options_read_by in cl/kernel_source.h); and the translucent shadow stage of
// --indirect afs and dual.
constexpr const char* kTraceProgram = "stages/trace.cl";
constexpr const char* kShadeProgram = "stages/shade.cl";
constexpr const char* kAfsShadowProgram = "stages/intersect_shadow_afs.cl";  // --indirect afs and dual only
constexpr const char* kListsProgram = "stages/lists.cl";  // camera or shadow lists only

// The builds a scene with `features` needs, shade first (the longest: it starts first); the
// lists' stages (kListsProgram) come when the render makes lists (prefetch_lists_program).
std::vector<const char*> render_program_files(const KernelFeatures& features) {
    std::vector<const char*> files = {kShadeProgram, kTraceProgram};
    if (features[Feature::INDIRECT_AFS] || features[Feature::INDIRECT_DUAL]) files.push_back(kAfsShadowProgram);
    return files;
}

// True when upload_geometry will cut nothing into pages: the planner it uses keeps every array
// in one buffer even with twice as many BVH nodes and leaf references as primitives.
bool surely_unpaged(const Scene& scene, uint64_t max_alloc) {
    size_t triangles = 0;
    for (const Mesh& m : scene.meshes) triangles += m.triangle_count();
    const uint64_t primitives = scene.strands.segment_count() + triangles;
    try {
        return plan_geometry_pages({{"BVH node", 2 * primitives * sizeof(HtBvhNode)},
                                    {"segment", 2 * primitives * sizeof(HtSegment)},
                                    {"point", (scene.strands.point_count() + 3 * triangles) * sizeof(HtPoint)},
                                    {"triangle shading", triangles * sizeof(HtTriangleShading)}},
                                   max_alloc)
                   .pages == 1;
    } catch (const DeviceError&) {
        return false;  // more pages than the kernels take: the upload will say so
    }
}
}  // namespace

std::string render_program_options(KernelFeatures features, const std::string& estimator_options,
                                   const GeometryPaging& paging) {
    features.paging = paging;
    return kernel_build_options(features) + estimator_options;
}

namespace {
void prefetch_programs(ClContext& cl, const PreparedScene& recipe, const Scene& scene,
                       const std::vector<const char*>& files) {
    if (!surely_unpaged(scene, cl.info().max_alloc)) return;
    const std::string options = render_program_options(recipe.features, recipe.estimator_options, GeometryPaging{});
    for (const char* file : files) cl.prefetch(file, options);
}
}  // namespace

void prefetch_render_program(ClContext& cl, const PreparedScene& recipe, const Scene& scene) {
    prefetch_programs(cl, recipe, scene, render_program_files(recipe.features));
}

void prefetch_lists_program(ClContext& cl, const PreparedScene& recipe, const Scene& scene) {
    prefetch_programs(cl, recipe, scene, {kListsProgram});
}

// Test hook: HAIRTRACE_INJECT_FAULT=alloc|launch makes the device layer fail the way a driver
// does (CL_MEM_OBJECT_ALLOCATION_FAILURE, CL_OUT_OF_RESOURCES), so the error paths that real
// devices reach only under pressure are exercised by tests (tests/render/failure_test.cpp).
static bool injected_fault(const char* where) {
    static const std::string fault = [] {
        const char* e = std::getenv("HAIRTRACE_INJECT_FAULT");
        return std::string(e ? e : "");
    }();
    return !fault.empty() && fault == where;
}

struct Renderer::Impl {
    ClContext& cl;
    std::unique_ptr<PreparedScene> owned;  // when constructed from a Scene
    const PreparedScene& prepared;
    const RenderSettings& settings;
    DeviceGeometry device_geometry;
    SceneBuffers scene;
    cl::Buffer afs_table;   // --indirect afs: AFS_TT^avg(theta) per material
    cl::Buffer dual_table;  // --indirect dual: kernels/fiber/dual.h's table per material
    std::string options;
    KernelFeatures features;
    cl::Program trace_program, shade_program;
    cl::Kernel k_generate, k_closest, k_closest_paths, k_camera, k_shade, k_shadow, k_resolve, k_accumulate,
        k_accumulate_background;
    // The camera rays' candidate lists (render/candidate_lists.h), when the scene has them
    struct CandidateLists {
        cl::Buffer start, count, primitive, depth, leaf_node;
        cl_float4 depth_row{};
    } candidate_lists;
    bool use_candidate_lists = false;
    // lists the memory plan left on the host (plan_memory_dropping_lists), and a path grid that
    // does not fit the device's buffers (keep_path_grid_if_it_fits)
    uint64_t dropped_list_bytes = 0;
    // how the prepared scene's large arrays reach the device: the geometry's and the lists' alike
    // (bvh/device_geometry.h; the prepared scene outlives the renderer, unchanged, and is read
    // throughout, so its arrays can be the buffers)
    GeometryMemory memory = GeometryMemory::Copy;
    // The lights' shadow lists (render/shadow_lists.h), when the scene has them
    struct ShadowListBuffers {
        cl::Buffer grids, start, count, primitive, key;
        cl_uint grid_count = 0;
    } shadow_lists;
    cl::Kernel k_shadow_lists;
    // The path rays' grid (render/path_grid.h), when the trace program walks it (features[PATH_GRID])
    PathGridBuffers path_grid;
    cl::Kernel k_compact_count, k_compact_scan, k_compact_scatter;
    cl::Kernel k_shadow_afs, k_resolve_afs, k_shadow_dual;
    cl::Kernel k_pilot_record, k_pilot_accumulate;  // --first-hit-splits auto's pilot
    // --light-vertices (kernels/integrator/light_vertices.h): PreparedScene::light_vertices with the
    // pass's first sample; the pass's light rays and their hits (grown to count x samples of the
    // largest pass)
    bool light_vertices = false;
    HtLightVertices lv{};
    cl::Buffer light_rays, light_hits;
    size_t light_ray_capacity = 0;
    cl::Kernel k_generate_light;
    RenderStats stats;
    cl::Buffer film_buf, film_aov;  // film_aov: --aovs only
    cl::Buffer film_even;           // --target-error: the even samples' half film (core/film.h)
    cl::Buffer pixel_list;          // set_pixels; a one-element dummy while every pixel renders
    size_t listed_pixels = 0;       // 0: every pixel
    // The pixels one sample renders: `count` of them from `list`; no list: every pixel.
    struct PixelSelection {
        const cl::Buffer* list = nullptr;
        size_t count = 0;
    };
    // Pixels that see no geometry (render/pixel_footprint.h), when they are skipped: a sample over
    // every pixel traces seen_list only and adds `background` (what a camera ray that misses
    // brings back, sample count 1 in w) to the empty ones.  empty_count 0: nothing skipped.
    cl::Buffer seen_list, empty_list;
    size_t seen_count = 0, empty_count = 0;
    cl_float4 background{{0.0f, 0.0f, 0.0f, 1.0f}};
    RayDump* dump = nullptr;        // --dump-rays
    PixelSelection render_selection() const;  // the pixels a sample of the render traces

    // per-pass buffers (render/path_buffers.h), sized for max paths per pass
    PathBufferSet buffer_set;
    size_t capacity = 0;         // path slots per pass
    size_t camera_paths_per_pass = 0;  // capacity / paths_per_pixel
    // --first-hit-splits, or 1 where no path goes on past its first vertex (depth 1 without an
    // environment): there is nothing to split, and the image is the same either way.  auto: the
    // pilot's N until the pilot has run (splits_pending), then its choice.
    uint32_t splits = 1;
    bool can_split = false;  // a path can go on past its first vertex
    bool splits_pending = false;
    uint32_t seed = 0;  // settings.seed; the pilot's own while it runs (render/split_choice.h)
    // While the pilot runs: each path slot's first-vertex radiance, and the pilot pixels' moments
    // (kernels/stages/split_pilot.cl).
    struct Pilot {
        cl::Buffer first_vertex, moments;
        uint32_t half = 0;  // which of its two seeds
    };
    Pilot* pilot = nullptr;
    uint32_t light_samples = 1;    // --first-hit-light-samples
    uint32_t paths_per_pixel = 1;  // path states of a camera path: max(splits, light_samples)
    WorkBuffer buffers[size_t(PathBuffer::Count)];
    cl::Buffer counters;

    cl::Buffer& buffer(PathBuffer b) { return buffers[size_t(b)].buffer(); }
    cl::Buffer& queue_rays(int q) { return buffer(q ? PathBuffer::RaysB : PathBuffer::RaysA); }
    cl::Buffer& queue_paths(int q) { return buffer(q ? PathBuffer::RayPathB : PathBuffer::RayPathA); }

    // Commands still queued (a render left by an exception) may use the path buffers' host memory
    // (cl/work_buffer.h): they finish before it goes.
    ~Impl() {
        try {
            cl.queue().finish();
        } catch (...) {
        }
    }

    Impl(ClContext& c, std::unique_ptr<PreparedScene> own, const PreparedScene& p, GeometryMemory geometry)
        : cl(c), owned(std::move(own)), prepared(p), settings(p.settings), memory(geometry) {
        const RenderSettings& s = settings;
        device_geometry = upload_geometry(cl, p.geometry, 0, memory);
        scene.strand_material = device_array(cl.context(), p.strand_material);
        scene.materials = device_array(cl.context(), p.materials);
        scene.light_count = cl_uint(p.lights.size());
        scene.lights = device_array(cl.context(), p.lights);
        scene.environment = p.environment.header;
        scene.env_texels = device_array(cl.context(), p.environment.texels);
        scene.env_marginal = device_array(cl.context(), p.environment.marginal);
        scene.env_conditional = device_array(cl.context(), p.environment.conditional);

        const bool afs = s.indirect == RenderSettings::Indirect::Afs;
        buffer_set.indirect_afs = afs;
        const bool dual = s.indirect == RenderSettings::Indirect::Dual;
        buffer_set.indirect_dual = dual;
        buffer_set.aovs = s.aovs;
        light_vertices = s.light_vertices > 0;  // prepare_scene left it on only where it connects
        buffer_set.light_vertices = light_vertices;
        lv = p.light_vertices;
        seed = s.seed;
        can_split = s.max_depth > 1 || p.environment.header.enabled;
        splits_pending = can_split && s.first_hit_splits == kAutoFirstHitSplits;
        splits = !can_split ? 1u : splits_pending ? uint32_t(kPilotSplits) : uint32_t(s.first_hit_splits);
        light_samples = uint32_t(s.first_hit_light_samples);
        paths_per_pixel = std::max(splits, light_samples);
        buffer_set.slots_per_pixel = paths_per_pixel;
        stats.clamp_indirect = s.clamp_indirect;
        stats.light_guiding = p.settings.light_guiding;
        // The render identity (render/render_identity.h) leaves the paging out: it depends on
        // the device, and paged and unpaged renders give the same bits (tested).
        features = p.features;
        keep_path_grid_if_it_fits();
        options = kernel_build_options(features) + p.estimator_options;
        features.paging = device_geometry.paging;
        const std::string build_options = render_program_options(features, p.estimator_options, features.paging);
        stats.build_cached = true;
        const auto build = [&](const char* file) {
            cl::Program program = cl.build(file, build_options);
            stats.build_ms += cl.last_build_ms();
            stats.build_cached = stats.build_cached && cl.last_build_cached();
            return program;
        };
        shade_program = build(kShadeProgram);
        trace_program = build(kTraceProgram);
        stats.kernel_options = build_options;
        k_generate = cl::Kernel(trace_program, "generate_camera_rays");
        k_closest_paths = cl::Kernel(trace_program, "intersect_closest_paths");
        k_shade = cl::Kernel(shade_program, "shade");
        k_shadow = cl::Kernel(trace_program, "intersect_shadow");
        k_resolve = cl::Kernel(trace_program, "resolve_shadows");
        k_accumulate = cl::Kernel(trace_program, "accumulate");
        k_accumulate_background = cl::Kernel(trace_program, "accumulate_background");
        k_compact_count = cl::Kernel(trace_program, "compact_count");
        k_compact_scan = cl::Kernel(trace_program, "compact_scan");
        k_compact_scatter = cl::Kernel(trace_program, "compact_scatter");
        if (light_vertices) {  // the program holds them only then (kernels/stages/trace.cl)
            k_generate_light = cl::Kernel(trace_program, "generate_light_rays");
            k_closest = cl::Kernel(trace_program, "intersect_closest");
        }
        if (splits_pending) {
            k_pilot_record = cl::Kernel(trace_program, "pilot_record_first_vertex");
            k_pilot_accumulate = cl::Kernel(trace_program, "pilot_accumulate");
        }
        if (afs) {
            afs_table = device_array(cl.context(), p.afs_table);
            const cl::Program afs_program = build(kAfsShadowProgram);
            k_shadow_afs = cl::Kernel(afs_program, "intersect_shadow_afs");
            k_resolve_afs = cl::Kernel(afs_program, "resolve_shadows_afs");
        }
        if (dual) {
            dual_table = device_array(cl.context(), p.dual_table);
            k_shadow_dual = cl::Kernel(build(kAfsShadowProgram), "shadow_dual");
        }

        upload_pixel_lists();  // before the plan, which counts them
        // the plan decides which lists fit before any is allocated on the device
        const MemoryPlan plan = plan_memory_dropping_lists();
        upload_candidate_lists();
        upload_shadow_lists();
        upload_path_grid();
        if (use_candidate_lists || shadow_lists.grid_count > 0) {  // lists that reach the device
            const cl::Program lists_program = build(kListsProgram);
            if (use_candidate_lists) k_camera = cl::Kernel(lists_program, "intersect_camera");
            if (shadow_lists.grid_count > 0) k_shadow_lists = cl::Kernel(lists_program, "intersect_shadow_lists");
        }
        upload_textures();
        use_plan(plan);
        pixel_list = device_array(cl.context(), std::vector<cl_uint>{});
    }

    // The pixels that see no geometry (prepare_scene finds them where their value is the same in
    // every sample: not with an environment map, whose texels a pixel's rays see differently, nor
    // with --aovs, whose miss values are not filled in).  A camera ray that misses brings back the
    // environment's radiance with throughput 1 and no clamp (kernels/stages/shade.cl), which
    // accumulate adds to the pixel's sums with count 1: background is that float4, so the skipped
    // pixels' sums are the traced ones' bit for bit (tested).
    void upload_pixel_lists() {
        const PixelFootprint& footprint = prepared.footprint;
        const HtEnvironment& env = prepared.environment.header;
        stats.footprint_ms = prepared.footprint_ms;
        if (footprint.empty.empty()) return;
        seen_list = device_array(cl.context(), footprint.seen);
        empty_list = device_array(cl.context(), footprint.empty);
        seen_count = footprint.seen.size();
        empty_count = footprint.empty.size();
        stats.empty_pixels = empty_count;
        if (env.enabled) background = cl_float4{{env.scale[0], env.scale[1], env.scale[2], 1.0f}};
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(background.s[c])) background.s[c] = 0.0f;  // shade drops it the same way
    }

    void upload_candidate_lists() {
        const PixelCandidates& c = prepared.candidates;
        if (!c.enabled) return;
        stats.candidates_ms = prepared.candidates_ms;  // made, whether it fits or not
        if (stats.camera_lists_dropped) return;
        candidate_lists.start = device_array(cl.context(), c.start);
        candidate_lists.count = device_array(cl.context(), c.count);
        candidate_lists.primitive = list_array("camera lists' primitives", c.primitive);
        candidate_lists.depth = list_array("camera lists' depths", c.depth);
        candidate_lists.leaf_node = device_array(cl.context(), c.leaf_node);
        candidate_lists.depth_row = cl_float4{{c.depth_row[0], c.depth_row[1], c.depth_row[2], 0.0f}};
        use_candidate_lists = true;
        stats.candidate_tree_pixels = c.tree_pixels;
        stats.candidate_entries = c.primitive.size();
    }

    // A list's entries, tens of megabytes on a lock: on a CPU device the prepared scene's own
    // pages where `memory` shares them (no copy, no fresh pages to fault in, the huge pages kept).
    template <typename T> cl::Buffer list_array(const char* what, const BulkVector<T>& v) {
        return read_only_buffer(cl, what, v.data(), v.size() * sizeof(T), memory);
    }

    void upload_shadow_lists() {
        const ShadowLists& l = prepared.shadow_lists;
        if (!l.enabled()) return;
        stats.shadow_lists_ms = prepared.shadow_lists_ms;  // made, whether they fit or not
        if (stats.shadow_lists_dropped) return;
        shadow_lists.grids = device_array(cl.context(), l.grids);
        shadow_lists.start = device_array(cl.context(), l.start);
        shadow_lists.count = device_array(cl.context(), l.count);
        shadow_lists.primitive = list_array("shadow lists' primitives", l.primitive);
        shadow_lists.key = list_array("shadow lists' keys", l.key);
        shadow_lists.grid_count = cl_uint(l.grids.size());
        stats.shadow_list_entries = l.primitive.size();
    }

    // The grid's arrays each need one buffer (the kernel walks them unpaged): a device that
    // allocates less takes the path rays by the tree when --path-rays auto chose the grid (the
    // same image; the trace program is then built without it), and refuses --path-rays grid with
    // the sizes.  The grid is usually the scene's largest array, so this is where a small device
    // or a paged scene meets it.
    void keep_path_grid_if_it_fits() {
        if (!features[Feature::PATH_GRID]) return;
        const PathGrid& g = prepared.path_grid;
        const uint64_t max_alloc = cl.info().max_alloc;
        if (g.fits_buffers(max_alloc)) return;
        if (settings.path_rays == RenderSettings::PathRays::Grid)
            throw DeviceError("the path rays' grid needs " + format_bytes(g.largest_array_bytes()) + " in one buffer but the device " +
                              cl.info().name + " allocates at most " + format_bytes(max_alloc) +
                              " per buffer; render with --path-rays tree or auto");
        features[Feature::PATH_GRID] = false;
        dropped_list_bytes += g.bytes();
        stats.path_grid_dropped = true;
    }

    // The grid is compiled into the trace program (the recipe chose it and it fits one buffer per
    // array), so it reaches the device or the render fails with the allocation's error; it is
    // counted in the plan's scene bytes.
    void upload_path_grid() {
        if (!features[Feature::PATH_GRID]) return;
        const PathGrid& g = prepared.path_grid;
        if (g.empty())
            throw DeviceError("the path rays' grid could not be made (more than 2^32 entries); render with --path-rays tree");
        path_grid.cells = list_array("path rays' grid cells", g.cell_start);
        path_grid.entries = list_array("path rays' grid entries", g.entries);
        path_grid.grid = g.grid;
        stats.path_grid_ms = prepared.path_grid_ms;
        stats.path_grid_cells = g.cells();
        stats.path_grid_occupied = g.occupied_cells();
        stats.path_grid_entries = g.entries.size();
    }

    MemoryPlan plan_memory() const {
        const RenderSettings& s = settings;
        // the lists of the pixels that see geometry and of those that do not: 4 bytes per pixel
        const uint64_t pixel_lists = empty_count > 0 ? 4 * uint64_t(s.width) * uint64_t(s.height) : 0;
        const uint64_t scene_bytes = device_geometry.bytes + prepared.extra_scene_bytes() - dropped_list_bytes + pixel_lists;
        // a pass holds every traced pixel, each for up to --samples-per-pass samples, while that
        // stays within kSamplesPerPassPaths camera paths (or one sample of the image)
        const uint64_t pixels = uint64_t(s.width) * uint64_t(s.height), traced = empty_count > 0 ? seen_count : pixels;
        const uint64_t camera_paths =
            std::max(pixels, std::min(traced * uint64_t(std::max(s.samples_per_pass, 1)), uint64_t(kSamplesPerPassPaths)));
        return plan_device_memory(pixels, camera_paths, scene_bytes, cl.info().max_alloc,
                                  cl.info().global_mem, s.max_device_bytes, std::max<size_t>(s.max_paths_per_pass, 1),
                                  buffer_set, device_geometry.paging);
    }

    // The candidate and shadow lists only make rays faster, with the tree's answers: a render that
    // would fit the device without them leaves them on the host instead of failing -- the shadow
    // lists first, which save less -- and says so in its statistics (upload_*_lists skip them).
    MemoryPlan plan_memory_dropping_lists() {
        for (;;) {
            try {
                return plan_memory();
            } catch (const DeviceError&) {
                if (prepared.shadow_lists.enabled() && !stats.shadow_lists_dropped) {
                    dropped_list_bytes += prepared.shadow_lists.bytes();
                    stats.shadow_lists_dropped = true;
                } else if (prepared.candidates.enabled && !stats.camera_lists_dropped) {
                    dropped_list_bytes += prepared.candidates.bytes();
                    stats.camera_lists_dropped = true;
                } else {
                    throw;
                }
            }
        }
    }

    void use_plan(const MemoryPlan& plan) {
        camera_paths_per_pass = plan.camera_paths_per_pass;
        allocate(plan.paths_per_pass);
    }

    // N continuations from now on; the pass buffers are planned again for N's path slots.
    void set_splits(uint32_t n) {
        splits = n;
        splits_pending = false;
        if (std::max(splits, light_samples) == paths_per_pixel) return;
        paths_per_pixel = std::max(splits, light_samples);
        buffer_set.slots_per_pixel = paths_per_pixel;
        use_plan(plan_memory());
    }

    // After the memory plan, so textures that cannot fit are refused before they are copied.
    void upload_textures() {
        const std::vector<HtTexture>& headers = prepared.texture_headers;
        const uint64_t texel_bytes = prepared.texel_bytes;
        if (cl.info().max_alloc && texel_bytes > cl.info().max_alloc)
            throw DeviceError("the scene's textures need " + format_bytes(texel_bytes) +
                              " in one buffer but the device " + cl.info().name + " allocates at most " +
                              format_bytes(cl.info().max_alloc) + " per buffer; use smaller textures");
        scene.texture_count = cl_uint(headers.size());
        scene.textures = device_array(cl.context(), headers);
        scene.texels = cl::Buffer(cl.context(), CL_MEM_READ_ONLY, texel_bytes);
        uint32_t table[HT_SRGB_TABLE_SIZE];
        ht_srgb_table(table);
        cl.queue().enqueueWriteBuffer(scene.texels, CL_TRUE, 0, sizeof table, table);
        for (size_t i = 0; prepared.textures && i < prepared.textures->size(); ++i) {
            const std::vector<uint32_t>& t = (*prepared.textures)[i].texels;
            if (!t.empty())
                cl.queue().enqueueWriteBuffer(scene.texels, CL_TRUE, size_t(headers[i].offset) * sizeof(uint32_t),
                                              t.size() * sizeof(uint32_t), t.data());
        }
    }

    void allocate(size_t n) {
        if (injected_fault("alloc")) throw cl::Error(CL_MEM_OBJECT_ALLOCATION_FAILURE, "clCreateBuffer");
        if (capacity) cl.queue().finish();  // the buffers replaced below may be host memory (WorkBuffer)
        capacity = n;
        for (const PathBufferSpec& b : kPathBuffers)
            if (buffer_set.uses(b)) buffers[size_t(b.id)] = WorkBuffer(cl, buffer_set.bytes(b, n));
        counters = cl::Buffer(cl.context(), CL_MEM_READ_WRITE, HT_COUNTER_COUNT * sizeof(uint32_t));
    }

    size_t selected_pixels(const PixelSelection& selected) const {
        return selected.list ? selected.count : size_t(settings.width) * size_t(settings.height);
    }

    // How many samples of the selected pixels one pass renders: --samples-per-pass when a pass
    // holds them all (else one, passes over the pixels as before); one while rays are dumped (a
    // dump lists them by sample).
    uint32_t samples_per_pass(const PixelSelection& selected) const {
        const size_t pixels = selected_pixels(selected);
        if (dump || pixels == 0) return 1;
        return uint32_t(std::clamp<size_t>(camera_paths_per_pass / pixels, 1, size_t(std::max(settings.samples_per_pass, 1))));
    }

    // Samples first .. first + samples - 1 of the selected pixels, pass by pass, each pass all
    // `samples` of its pixels (samples_per_pass); the pilot's when `pilot`.
    void trace_samples(uint32_t first, uint32_t samples, const PixelSelection& selected) {
        const RenderSettings& s = settings;
        const size_t pixels = selected_pixels(selected);
        const size_t pixels_per_pass = std::max<size_t>(camera_paths_per_pass / samples, 1);
        if (light_vertices) trace_light_vertices(first, samples);
        for (size_t offset = 0; offset < pixels; offset += pixels_per_pass) {
            const uint32_t pass_pixels = uint32_t(std::min(pixels_per_pass, pixels - offset));
            const uint32_t count = pass_pixels * samples;  // camera paths
            generate_camera_rays(uint32_t(offset), count, first, samples, selected);
            stats.camera_rays += count;
            stats.paths += uint64_t(count) * splits;
            int q = 0;
            uint32_t n = count;
            // max_depth scattering vertices; with an environment, the last vertex's BCSDF ray is
            // traced too, for the environment light it sees (kernels/stages/shade.cl)
            const uint32_t vertices = uint32_t(s.max_depth);
            const uint32_t traced = vertices + (scene.environment.enabled ? 1u : 0u);
            for (uint32_t bounce = 0; n > 0 && bounce < traced; ++bounce) {
                const auto t_bounce = std::chrono::steady_clock::now();
                // the nodes the tree's traversals start at (none when the path rays walk the grid,
                // which keeps no node: `bench` then times them from the root and by the grid)
                const std::vector<uint32_t> starts =
                    dump && !features[Feature::PATH_GRID] ? start_nodes(q, n) : std::vector<uint32_t>();
                if (bounce == 0 && use_candidate_lists)
                    intersect_camera(q, n);
                else
                    intersect_closest(q, n);
                if (dump) dump->closest(cl.queue(), queue_rays(q), buffer(PathBuffer::Hits), n, bounce, starts);
                shade(q, n, bounce);
                // the first shade leaves `light_samples` shadow slots and `splits` stage slots
                // per camera ray, later ones one of each per ray
                const uint32_t shadow_slots = bounce == 0 ? n * light_samples : n;
                if (bounce + 1 == vertices && s.indirect == RenderSettings::Indirect::Afs) {
                    intersect_shadow_afs(shadow_slots);
                    resolve_shadows_afs(shadow_slots);
                } else if (bounce + 1 == vertices && s.indirect == RenderSettings::Indirect::Dual) {
                    shadow_dual(shadow_slots);
                } else if (bounce < vertices) {
                    intersect_shadow(shadow_slots);
                    if (dump) dump->shadow(cl.queue(), buffer(PathBuffer::ShadowRays), buffer(PathBuffer::Occluded), shadow_slots, bounce);
                    resolve_shadows(shadow_slots);
                    // the connections to light vertices, one slot per shaded ray, after the
                    // estimates' slots (a path may have one of each)
                    if (light_vertices && bounce + 1 < vertices) {
                        intersect_shadow(buffer(PathBuffer::ConnectRays), buffer(PathBuffer::ConnectOccluded), n, false);
                        resolve_shadows(buffer(PathBuffer::ConnectContrib), buffer(PathBuffer::ConnectOccluded), n);
                    }
                }
                if (pilot && bounce == 0) pilot_record_first_vertex(count);
                const uint32_t staged = bounce == 0 ? n * splits : n;
                if (bounce + 1 < traced) compact(1 - q, staged);  // else no path continues
                const ShadeCounters c = read_counters();
                stats.nonfinite_caught += c.nonfinite;
                stats.shadow_rays += c.shadow;
                stats.extension_rays += c.next;
                stats.cut_paths += c.cut;
                if (stats.bounces.size() <= bounce) stats.bounces.resize(bounce + 1);
                BounceStats& bs = stats.bounces[bounce];
                bs.paths += n;
                bs.shadow_rays += c.shadow;
                bs.cut_paths += c.cut;
                // read_counters() waited for the queue: this is the bounce's wall time
                bs.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_bounce).count();
                q = 1 - q;
                n = c.next;
            }
            if (pilot)
                pilot_accumulate(pass_pixels, samples, uint32_t(offset));
            else
                accumulate(film_buf, pass_pixels, samples);
        }
        cl.queue().finish();
    }

    // The light rays of samples first .. first + samples - 1 and their first hits.
    void trace_light_vertices(uint32_t first, uint32_t samples) {
        const size_t n = size_t(lv.count) * samples;
        if (n > light_ray_capacity) {
            light_rays = cl::Buffer(cl.context(), CL_MEM_READ_WRITE, n * sizeof(HtRay));
            light_hits = cl::Buffer(cl.context(), CL_MEM_READ_WRITE, n * sizeof(HtHit));
            light_ray_capacity = n;
        }
        lv.first_sample = first;
        cl_uint a = 0;
        k_generate_light.setArg(a++, lv);
        k_generate_light.setArg(a++, scene.lights);
        k_generate_light.setArg(a++, scene.light_count);
        k_generate_light.setArg(a++, seed);
        k_generate_light.setArg(a++, cl_uint(n));
        k_generate_light.setArg(a++, light_rays);
        launch(k_generate_light, n);
        intersect_closest(light_rays, light_hits, uint32_t(n));
        stats.light_rays += n;
    }

    // ---- stages ---------------------------------------------------------------------------
    // The traversal's arrays, paged or not (kernels/geometry/pages.h); returns the next argument.
    cl_uint set_geometry_args(cl::Kernel& k) {
        cl_uint a = set_paged_args(k, 0, device_geometry.nodes);
        a = set_paged_args(k, a, device_geometry.segments);
        return set_paged_args(k, a, device_geometry.points);
    }

    void generate_camera_rays(uint32_t offset, uint32_t count, uint32_t first, uint32_t samples,
                              const PixelSelection& selected) {
        cl_uint a = 0;
        k_generate.setArg(a++, prepared.camera);
        k_generate.setArg(a++, offset);
        k_generate.setArg(a++, count);
        k_generate.setArg(a++, seed);
        k_generate.setArg(a++, first);
        k_generate.setArg(a++, samples);
        k_generate.setArg(a++, cl_uint(paths_per_pixel));
        k_generate.setArg(a++, selected.list ? *selected.list : pixel_list);  // unread without a list: any buffer
        k_generate.setArg(a++, cl_uint(selected.list != nullptr));
        k_generate.setArg(a++, queue_rays(0));
        k_generate.setArg(a++, queue_paths(0));
        k_generate.setArg(a++, buffer(PathBuffer::Paths));
        launch(k_generate, count);
    }

    // The arguments the closest-hit stages of queue q share: geometry, the rays, their hits and
    // paths (whose states say where each ray's traversal starts); returns the next argument.
    cl_uint set_closest_queue_args(cl::Kernel& k, int q, uint32_t count) {
        cl_uint a = set_geometry_args(k);
        k.setArg(a++, queue_rays(q));
        k.setArg(a++, buffer(PathBuffer::Hits));
        k.setArg(a++, count);
        k.setArg(a++, queue_paths(q));
        k.setArg(a++, buffer(PathBuffer::Paths));
        return a;
    }

    // The nodes where the traversals of queue q's first `count` rays start (their paths' last hit
    // nodes), for --dump-rays.
    std::vector<uint32_t> start_nodes(int q, uint32_t count) {
        std::vector<uint32_t> ray_path(count), starts(count);
        std::vector<HtPathState> paths(capacity);
        cl.queue().enqueueReadBuffer(queue_paths(q), CL_FALSE, 0, count * sizeof(uint32_t), ray_path.data());
        cl.queue().enqueueReadBuffer(buffer(PathBuffer::Paths), CL_TRUE, 0, capacity * sizeof(HtPathState), paths.data());
        for (uint32_t i = 0; i < count; ++i) starts[i] = paths.at(ray_path[i]).node;
        return starts;
    }

    // The rays of queue q, each starting its traversal at the node of its path's last hit
    // (kernels/stages/intersect_closest_paths.cl).
    void intersect_closest(int q, uint32_t count) {
        const cl_uint a = set_closest_queue_args(k_closest_paths, q, count);
        if (features[Feature::PATH_GRID]) set_bundle_args(k_closest_paths, a, path_grid);
        launch(k_closest_paths, count);
    }

    void intersect_closest(const cl::Buffer& rays, const cl::Buffer& hits, uint32_t count) {
        cl_uint a = set_geometry_args(k_closest);
        k_closest.setArg(a++, rays);
        k_closest.setArg(a++, hits);
        k_closest.setArg(a++, count);
        launch(k_closest, count);
    }

    // The camera rays of queue q, through their pixels' candidate lists.
    void intersect_camera(int q, uint32_t count) {
        cl_uint a = set_closest_queue_args(k_camera, q, count);
        k_camera.setArg(a++, candidate_lists.start);
        k_camera.setArg(a++, candidate_lists.count);
        k_camera.setArg(a++, candidate_lists.primitive);
        k_camera.setArg(a++, candidate_lists.depth);
        k_camera.setArg(a++, candidate_lists.depth_row);
        k_camera.setArg(a++, candidate_lists.leaf_node);
        launch(k_camera, count);
    }

    void shade(int q, uint32_t count, uint32_t bounce) {
        static const uint32_t zero[HT_COUNTER_COUNT] = {0, 0, 0, 0};
        cl.queue().enqueueWriteBuffer(counters, CL_FALSE, 0, sizeof zero, zero);
        cl_uint a = 0;
        a = set_paged_args(k_shade, a, device_geometry.segments);
        a = set_paged_args(k_shade, a, device_geometry.points);
        a = set_paged_args(k_shade, a, device_geometry.triangles);
        a = set_bundle_args(k_shade, a, scene);
        const ShadeQueue queue{queue_rays(q), buffer(PathBuffer::Hits), queue_paths(q), count,
                               buffer(PathBuffer::Paths), buffer(PathBuffer::ShadowRays),
                               buffer(PathBuffer::ShadowContrib), buffer(PathBuffer::StageRays),
                               buffer(PathBuffer::StagePath), counters};
        a = set_bundle_args(k_shade, a, queue);
        const HtBounce b{seed, 0, bounce, uint32_t(settings.max_depth), settings.fiber_field,
                         prepared.pixel_angle, splits, light_samples};
        k_shade.setArg(a++, b);
        if (settings.aovs) {
            k_shade.setArg(a++, buffer(PathBuffer::Aovs));
            k_shade.setArg(a++, buffer(PathBuffer::ShadowAovs));
        }
        if (settings.indirect == RenderSettings::Indirect::Dual) k_shade.setArg(a++, buffer(PathBuffer::DualRecords));
        if (light_vertices) {
            k_shade.setArg(a++, light_rays);
            k_shade.setArg(a++, light_hits);
            k_shade.setArg(a++, lv);
            k_shade.setArg(a++, buffer(PathBuffer::ConnectRays));
            k_shade.setArg(a++, buffer(PathBuffer::ConnectContrib));
        }
        launch(k_shade, count);
    }

    // Packs the surviving paths' extension rays into queue `out`, in slot order.
    void compact(int out, uint32_t count) {
        const uint32_t groups = uint32_t(round_up(count, kLocalSize) / kLocalSize);
        k_compact_count.setArg(0, buffer(PathBuffer::StagePath));
        k_compact_count.setArg(1, count);
        k_compact_count.setArg(2, buffer(PathBuffer::GroupSums));
        launch(k_compact_count, count);
        k_compact_scan.setArg(0, buffer(PathBuffer::GroupSums));
        k_compact_scan.setArg(1, groups);
        k_compact_scan.setArg(2, counters);
        launch(k_compact_scan, cl::NDRange(1), cl::NDRange(1));
        k_compact_scatter.setArg(0, buffer(PathBuffer::StageRays));
        k_compact_scatter.setArg(1, buffer(PathBuffer::StagePath));
        k_compact_scatter.setArg(2, count);
        k_compact_scatter.setArg(3, buffer(PathBuffer::GroupSums));
        k_compact_scatter.setArg(4, queue_rays(out));
        k_compact_scatter.setArg(5, queue_paths(out));
        launch(k_compact_scatter, count);
    }

    // The last shade's queue counters (kernels/types.h)
    struct ShadeCounters {
        uint32_t shadow, next, nonfinite, cut;
    };
    ShadeCounters read_counters() {
        uint32_t out[HT_COUNTER_COUNT];
        cl.queue().enqueueReadBuffer(counters, CL_TRUE, 0, sizeof out, out);
        return {out[HT_COUNTER_SHADOW], out[HT_COUNTER_NEXT], out[HT_COUNTER_NAN], out[HT_COUNTER_CUT]};
    }

    // With shadow lists, intersect_shadow_lists: intersect_shadow's arguments, then the lists.
    void intersect_shadow(uint32_t count) {
        intersect_shadow(buffer(PathBuffer::ShadowRays), buffer(PathBuffer::Occluded), count, true);
    }

    // Any rays (the lists serve only rays towards a light with a grid: `lists` says these are).
    void intersect_shadow(const cl::Buffer& rays, const cl::Buffer& occluded, uint32_t count, bool lists) {
        const bool use_lists = lists && shadow_lists.grid_count > 0;
        cl::Kernel& k = use_lists ? k_shadow_lists : k_shadow;
        cl_uint a = set_geometry_args(k);
        k.setArg(a++, rays);
        k.setArg(a++, occluded);
        k.setArg(a++, count);
        if (!use_lists && features[Feature::PATH_GRID]) a = set_bundle_args(k, a, path_grid);  // intersect_shadow.cl walks the grid
        if (use_lists) {
            k.setArg(a++, shadow_lists.grid_count);
            k.setArg(a++, shadow_lists.grids);
            k.setArg(a++, shadow_lists.start);
            k.setArg(a++, shadow_lists.count);
            k.setArg(a++, shadow_lists.primitive);
            k.setArg(a++, shadow_lists.key);
        }
        launch(k, use_lists ? ht_shadow_list_items(count) : count);  // several rays per work-item
    }

    // The arguments the translucent shadow stages share: geometry, the strands' materials, the
    // per-fibre table, the shadow rays; returns the next argument.
    cl_uint set_translucent_args(cl::Kernel& k, const cl::Buffer& table) {
        cl_uint a = set_geometry_args(k);
        k.setArg(a++, scene.strand_material);
        k.setArg(a++, table);
        k.setArg(a++, buffer(PathBuffer::ShadowRays));
        return a;
    }

    void intersect_shadow_afs(uint32_t count) {
        cl_uint a = set_translucent_args(k_shadow_afs, afs_table);
        k_shadow_afs.setArg(a++, buffer(PathBuffer::Transmittance));
        k_shadow_afs.setArg(a++, count);
        launch(k_shadow_afs, count);
    }

    // --indirect dual: walks the shadow rays through hair and adds each light sample's exact
    // single scattering and dual-scattering terms (kernels/stages/intersect_shadow_afs.cl).
    void shadow_dual(uint32_t count) {
        cl_uint a = set_translucent_args(k_shadow_dual, dual_table);
        k_shadow_dual.setArg(a++, buffer(PathBuffer::ShadowContrib));
        k_shadow_dual.setArg(a++, buffer(PathBuffer::DualRecords));
        k_shadow_dual.setArg(a++, count);
        k_shadow_dual.setArg(a++, buffer(PathBuffer::Paths));
        k_shadow_dual.setArg(a++, counters);
        launch(k_shadow_dual, count);
    }

    void resolve_shadows_afs(uint32_t count) {
        k_resolve_afs.setArg(0, buffer(PathBuffer::ShadowContrib));
        k_resolve_afs.setArg(1, buffer(PathBuffer::Transmittance));
        k_resolve_afs.setArg(2, count);
        k_resolve_afs.setArg(3, buffer(PathBuffer::Paths));
        set_resolve_aov_args(k_resolve_afs, 4);
        launch(k_resolve_afs, count);
    }

    void set_resolve_aov_args(cl::Kernel& k, cl_uint a) {
        if (!settings.aovs) return;
        k.setArg(a, buffer(PathBuffer::Aovs));
        k.setArg(a + 1, buffer(PathBuffer::ShadowAovs));
    }

    void resolve_shadows(uint32_t count) {
        resolve_shadows(buffer(PathBuffer::ShadowContrib), buffer(PathBuffer::Occluded), count);
    }

    void resolve_shadows(const cl::Buffer& contrib, const cl::Buffer& occluded, uint32_t count) {
        k_resolve.setArg(0, contrib);
        k_resolve.setArg(1, occluded);
        k_resolve.setArg(2, count);
        k_resolve.setArg(3, buffer(PathBuffer::Paths));
        set_resolve_aov_args(k_resolve, 4);
        launch(k_resolve, count);
    }

    // `pixels` pixels of the pass, `samples` samples each; with --target-error the even samples
    // also go to the even half film.
    void accumulate(cl::Buffer& film, uint32_t pixels, uint32_t samples) {
        const bool halves = settings.target_error > 0;
        cl_uint a = 0;
        k_accumulate.setArg(a++, buffer(PathBuffer::Paths));
        k_accumulate.setArg(a++, pixels);
        k_accumulate.setArg(a++, samples);
        k_accumulate.setArg(a++, cl_uint(paths_per_pixel));
        k_accumulate.setArg(a++, film);
        k_accumulate.setArg(a++, cl_uint(halves));
        k_accumulate.setArg(a++, halves ? film_even : pixel_list);  // unread without halves: any buffer
        if (settings.aovs) {
            k_accumulate.setArg(a++, buffer(PathBuffer::Aovs));
            k_accumulate.setArg(a++, film_aov);
        }
        launch(k_accumulate, pixels);
    }

    // The empty pixels' share of samples first .. first + samples - 1 (upload_pixel_lists).
    void accumulate_background(uint32_t first, uint32_t samples) {
        const bool halves = settings.target_error > 0;
        cl_uint a = 0;
        k_accumulate_background.setArg(a++, empty_list);
        k_accumulate_background.setArg(a++, cl_uint(empty_count));
        k_accumulate_background.setArg(a++, background);
        k_accumulate_background.setArg(a++, first);
        k_accumulate_background.setArg(a++, samples);
        k_accumulate_background.setArg(a++, film_buf);
        k_accumulate_background.setArg(a++, cl_uint(halves));
        k_accumulate_background.setArg(a++, halves ? film_even : empty_list);  // unread without halves: any buffer
        launch(k_accumulate_background, empty_count);
        stats.background_samples += uint64_t(empty_count) * samples;
    }

    void pilot_record_first_vertex(uint32_t cameras) {
        const uint32_t slots = cameras * paths_per_pixel;
        k_pilot_record.setArg(0, buffer(PathBuffer::Paths));
        k_pilot_record.setArg(1, slots);
        k_pilot_record.setArg(2, pilot->first_vertex);
        launch(k_pilot_record, slots);
    }

    void pilot_accumulate(uint32_t pixels, uint32_t samples, uint32_t list_offset) {
        cl_uint a = 0;
        k_pilot_accumulate.setArg(a++, buffer(PathBuffer::Paths));
        k_pilot_accumulate.setArg(a++, pilot->first_vertex);
        k_pilot_accumulate.setArg(a++, pixels);
        k_pilot_accumulate.setArg(a++, samples);
        k_pilot_accumulate.setArg(a++, cl_uint(paths_per_pixel));
        k_pilot_accumulate.setArg(a++, list_offset);
        k_pilot_accumulate.setArg(a++, pilot->half);
        k_pilot_accumulate.setArg(a++, pilot->moments);
        launch(k_pilot_accumulate, pixels);
    }

    // A film's AOV sums or even half on the device: a copy of `sums`, or zeros when it is empty
    // (a chunk's first upload).
    cl::Buffer film_sums(const std::vector<float>& sums, size_t floats, const char* what) {
        if (sums.empty()) {
            cl::Buffer b(cl.context(), CL_MEM_READ_WRITE, floats * sizeof(float));
            cl.queue().enqueueFillBuffer(b, 0.0f, 0, floats * sizeof(float));
            return b;
        }
        if (sums.size() != floats)
            throw std::invalid_argument(std::string("film ") + what + ": size does not match the render settings");
        return cl::Buffer(cl.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, floats * sizeof(float),
                          const_cast<float*>(sums.data()));
    }

    void launch(cl::Kernel& k, size_t n) { launch(k, global_for(n), cl::NDRange(kLocalSize)); }

    void launch(cl::Kernel& k, const cl::NDRange& global, const cl::NDRange& local) {
        if (injected_fault("launch")) throw cl::Error(CL_OUT_OF_RESOURCES, "clEnqueueNDRangeKernel");
        if (!settings.profile_stages) {
            cl.queue().enqueueNDRangeKernel(k, cl::NullRange, global, local);
            return;
        }
        cl.queue().finish();
        auto t0 = std::chrono::steady_clock::now();
        cl.queue().enqueueNDRangeKernel(k, cl::NullRange, global, local);
        cl.queue().finish();
        double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::string name = k.getInfo<CL_KERNEL_FUNCTION_NAME>();
        for (auto& [n, sec] : stats.stage_seconds)
            if (n == name) { sec += dt; return; }
        stats.stage_seconds.push_back({name, dt});
    }
};

Renderer::Renderer(ClContext& cl, const PreparedScene& prepared, GeometryMemory geometry) {
    try {
        impl_ = new Impl(cl, nullptr, prepared, geometry);
    } catch (const cl::Error& e) {
        throw DeviceError(std::string("OpenCL setup failed in ") + e.what() + ": " + cl_error_name(e.err()));
    }
}

Renderer::Renderer(ClContext& cl, const Scene& scene, const RenderSettings& settings) {
    try {
        auto own = std::make_unique<PreparedScene>(prepare_scene(
            scene, settings, [&](const PreparedScene& recipe) { prefetch_render_program(cl, recipe, scene); },
            [&](const PreparedScene& recipe) { prefetch_lists_program(cl, recipe, scene); }));
        const PreparedScene& p = *own;
        try {
            impl_ = new Impl(cl, std::move(own), p, GeometryMemory::Shared);
        } catch (const cl::Error& e) {
            throw DeviceError(std::string("OpenCL setup failed in ") + e.what() + ": " + cl_error_name(e.err()));
        }
    } catch (...) {
        cl.drop_prefetches();  // the compile this started is waited for now, not at the context's end
        throw;
    }
}
Renderer::~Renderer() { delete impl_; }
const std::string& Renderer::kernel_options() const { return impl_->options; }
const KernelFeatures& Renderer::features() const { return impl_->features; }
const RenderStats& Renderer::stats() const { return impl_->stats; }
void Renderer::set_ray_dump(RayDump* dump) {
    impl_->dump = dump;
    if (dump) dump->bind(impl_->prepared.geometry);
}

void Renderer::upload_film(const Film& film) {
    Impl& r = *impl_;
    const size_t floats = 4 * size_t(r.settings.width) * size_t(r.settings.height);
    if (film.rgba.size() != floats)
        throw std::invalid_argument("film size does not match the render settings");
    try {
        r.film_buf = cl::Buffer(r.cl.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                                floats * sizeof(float), const_cast<float*>(film.rgba.data()));
        if (r.settings.aovs) r.film_aov = r.film_sums(film.aov, size_t(HT_AOV_OUT) * (floats / 4), "AOV sums");
        if (r.settings.target_error > 0) r.film_even = r.film_sums(film.even, floats, "even half");
    } catch (const cl::Error& e) {
        throw DeviceError(std::string("cannot allocate the film on the device: ") + cl_error_name(e.err()));
    }
}

void Renderer::download_film(Film& film) {
    Impl& r = *impl_;
    film.width = r.settings.width;
    film.height = r.settings.height;
    film.rgba.resize(4 * size_t(film.width) * size_t(film.height));
    try {
        r.cl.queue().enqueueReadBuffer(r.film_buf, CL_TRUE, 0, film.rgba.size() * sizeof(float), film.rgba.data());
        film.aov.clear();
        if (r.settings.aovs) {
            film.aov.resize(size_t(HT_AOV_OUT) * size_t(film.width) * size_t(film.height));
            r.cl.queue().enqueueReadBuffer(r.film_aov, CL_TRUE, 0, film.aov.size() * sizeof(float), film.aov.data());
        }
        film.even.clear();
        if (r.settings.target_error > 0) {
            film.even.resize(film.rgba.size());
            r.cl.queue().enqueueReadBuffer(r.film_even, CL_TRUE, 0, film.even.size() * sizeof(float), film.even.data());
        }
    } catch (const cl::Error& e) {
        throw DeviceError(std::string("OpenCL failure reading the film: ") + cl_error_name(e.err()));
    }
}

void Renderer::set_pixels(const std::vector<uint32_t>& pixels) {
    Impl& r = *impl_;
    const size_t all = size_t(r.settings.width) * size_t(r.settings.height);
    for (size_t i = 0; i < pixels.size(); ++i)
        if (pixels[i] >= all || (i > 0 && pixels[i] <= pixels[i - 1]))
            throw std::invalid_argument("set_pixels: pixel indices must be ascending and inside the image");
    try {
        r.pixel_list = device_array(r.cl.context(), pixels);
    } catch (const cl::Error& e) {
        throw DeviceError(std::string("cannot allocate the pixel list on the device: ") + cl_error_name(e.err()));
    }
    r.listed_pixels = pixels.size();
}

void Renderer::render_sample(uint32_t sample) { render_samples(sample, 1); }

// A sample over every pixel traces those that may see geometry (perhaps none); not while rays are
// dumped (a dump holds every camera ray of the render).
Renderer::Impl::PixelSelection Renderer::Impl::render_selection() const {
    if (listed_pixels > 0) return {&pixel_list, listed_pixels};
    if (empty_count > 0 && !dump) return {&seen_list, seen_count};
    return {};
}

int Renderer::samples_per_pass() const {
    const Impl& r = *impl_;
    return int(r.samples_per_pass(r.render_selection()));
}

void Renderer::render_samples(uint32_t first, uint32_t count) {
    Impl& r = *impl_;
    if (r.splits_pending) choose_first_hit_splits();
    auto t0 = std::chrono::steady_clock::now();
    try {
        const Impl::PixelSelection selected = r.render_selection();
        const uint32_t per_pass = r.samples_per_pass(selected);
        for (uint32_t done = 0; done < count;) {
            const uint32_t n = std::min(per_pass, count - done);
            r.trace_samples(first + done, n, selected);
            if (selected.list == &r.seen_list) r.accumulate_background(first + done, n);
            done += n;
        }
    } catch (const cl::Error& e) {
        throw DeviceError(std::string("OpenCL failure in ") + e.what() + ": " + cl_error_name(e.err()));
    }
    r.stats.samples += count;
    r.stats.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

int Renderer::first_hit_splits() const { return impl_->splits_pending ? 0 : int(impl_->splits); }

void Renderer::set_first_hit_splits(int n) {
    if (n < 1 || n > kMaxFirstHitSplits) throw std::invalid_argument("set_first_hit_splits: N out of range");
    Impl& r = *impl_;
    if (!r.splits_pending && r.splits == uint32_t(n)) return;
    try {
        r.set_splits(uint32_t(n));
    } catch (const cl::Error& e) {
        throw DeviceError(std::string("cannot allocate the path buffers on the device: ") + cl_error_name(e.err()));
    }
}

SplitChoice Renderer::choose_first_hit_splits() {
    Impl& r = *impl_;
    SplitChoice choice;
    if (r.settings.first_hit_splits != kAutoFirstHitSplits || !r.can_split) {
        choice.splits = first_hit_splits();
        return choice;
    }
    const auto t0 = std::chrono::steady_clock::now();
    // the pilot runs with N = kPilotSplits, its own seed and pixels, and statistics of its own
    RenderStats render_stats = std::move(r.stats);
    r.stats = RenderStats{};
    RayDump* const render_dump = r.dump;
    std::vector<float> moments;
    try {
        if (!r.splits_pending) r.set_splits(uint32_t(kPilotSplits));  // chosen before: again
        const std::vector<uint32_t> pixels = pilot_pixels(r.settings.width, r.settings.height);
        const cl::Buffer pilot_list = device_array(r.cl.context(), pixels);
        r.dump = nullptr;
        moments.assign(16 * pixels.size(), 0.0f);
        Impl::Pilot pilot;
        pilot.moments = cl::Buffer(r.cl.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                                   moments.size() * sizeof(float), moments.data());
        // a pass of the pilot holds at most all its pixels, per_pass times: outside the memory
        // plan, but small
        const Impl::PixelSelection selected{&pilot_list, pixels.size()};
        const uint32_t per_pass = r.samples_per_pass(selected);
        const size_t slots = std::min(r.capacity, PathBufferSet::slots(pixels.size() * per_pass * r.paths_per_pixel));
        pilot.first_vertex = cl::Buffer(r.cl.context(), CL_MEM_READ_WRITE, slots * 4 * sizeof(float));
        r.pilot = &pilot;
        for (pilot.half = 0; pilot.half < 2; ++pilot.half) {
            r.seed = pilot_seed(r.settings.seed, int(pilot.half));
            for (uint32_t i = 0; i < uint32_t(kPilotSamples); i += per_pass)
                r.trace_samples(i, std::min(per_pass, uint32_t(kPilotSamples) - i), selected);
        }
        r.cl.queue().enqueueReadBuffer(pilot.moments, CL_TRUE, 0, moments.size() * sizeof(float), moments.data());
    } catch (const cl::Error& e) {
        r.pilot = nullptr;
        throw DeviceError(std::string("OpenCL failure in the first-hit splits' pilot, ") + e.what() + ": " +
                          cl_error_name(e.err()));
    }
    r.pilot = nullptr;
    choice.variance = split_variance(moments);
    choice.cost = split_cost(r.stats, kPilotSplits);
    choice.splits = best_splits(choice.variance, choice.cost);
    r.seed = r.settings.seed;
    r.dump = render_dump;
    r.stats = std::move(render_stats);
    set_first_hit_splits(choice.splits);
    choice.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return choice;
}

void RenderStats::add(const RenderStats& o) {
    camera_rays += o.camera_rays;
    background_samples += o.background_samples;
    empty_pixels = std::max(empty_pixels, o.empty_pixels);
    footprint_ms = std::max(footprint_ms, o.footprint_ms);
    candidate_tree_pixels = std::max(candidate_tree_pixels, o.candidate_tree_pixels);
    candidate_entries = std::max(candidate_entries, o.candidate_entries);
    candidates_ms = std::max(candidates_ms, o.candidates_ms);
    shadow_list_entries = std::max(shadow_list_entries, o.shadow_list_entries);
    shadow_lists_ms = std::max(shadow_lists_ms, o.shadow_lists_ms);
    path_grid_cells = std::max(path_grid_cells, o.path_grid_cells);
    path_grid_occupied = std::max(path_grid_occupied, o.path_grid_occupied);
    path_grid_entries = std::max(path_grid_entries, o.path_grid_entries);
    path_grid_ms = std::max(path_grid_ms, o.path_grid_ms);
    camera_lists_dropped = camera_lists_dropped || o.camera_lists_dropped;
    path_grid_dropped = path_grid_dropped || o.path_grid_dropped;
    shadow_lists_dropped = shadow_lists_dropped || o.shadow_lists_dropped;
    paths += o.paths;
    extension_rays += o.extension_rays;
    shadow_rays += o.shadow_rays;
    light_rays += o.light_rays;
    nonfinite_caught += o.nonfinite_caught;
    cut_paths += o.cut_paths;
    build_ms += o.build_ms;
    build_cached = o.build_cached;
    for (auto& stage : o.stage_seconds) stage_seconds.push_back(stage);
    if (bounces.size() < o.bounces.size()) bounces.resize(o.bounces.size());
    for (size_t b = 0; b < o.bounces.size(); ++b) {
        bounces[b].paths += o.bounces[b].paths;
        bounces[b].shadow_rays += o.bounces[b].shadow_rays;
        bounces[b].cut_paths += o.bounces[b].cut_paths;
        bounces[b].seconds += o.bounces[b].seconds;
    }
}

RenderStats Renderer::render(Film& film, const ProgressFn& progress) {
    const RenderSettings& s = impl_->settings;
    const size_t pixels = size_t(s.width) * size_t(s.height);
    if (film.width != s.width || film.height != s.height || film.rgba.size() != 4 * pixels) {
        film.width = s.width;
        film.height = s.height;
        film.rgba.assign(4 * pixels, 0.0f);
    }
    upload_film(film);
    for (int si = 0; si < s.spp;) {
        const int n = std::min(samples_per_pass(), s.spp - si);
        render_samples(uint32_t(s.first_sample + si), uint32_t(n));
        si += n;
        if (progress && !progress(si, s.spp)) break;
    }
    download_film(film);
    return impl_->stats;
}

}  // namespace ht
