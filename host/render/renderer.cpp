// The wavefront render loop.  One pass = one sample for a block of pixels; each pass runs the
// stages below until the extension queue is empty or max_depth is reached:
//
//   generate_camera_rays -> [ intersect_closest -> shade -> intersect_shadow -> resolve_shadows ]*
//                        -> accumulate
//
// Queue sizes come back from the device after each shade (one small read); empty queues
// launch nothing.
#include "render/renderer.h"

#include "bvh/bvh.h"
#include "bvh/device_geometry.h"
#include "core/constants.h"
#include "render/environment.h"
#include "render/features.h"
#include "render/memory_plan.h"
#include "render/ray_dump.h"
#include "render/scene_upload.h"
#include "fiber/afs_quadrature.h"
#include "kernels/fiber/afs.h"
#include "kernels/surface/texture.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <string>
#include <cmath>
#include <cstdio>

namespace ht {

namespace {
// docs/POCL.md §1: 32-256 are equal for traversal; 64 is also what compact.cl requires.
constexpr size_t kLocalSize = 64;

cl::NDRange global_for(size_t n) { return cl::NDRange(round_up(std::max<size_t>(n, 1), kLocalSize)); }

template <typename T>
cl::Buffer device_array(cl::Context& ctx, const std::vector<T>& v) {
    // OpenCL refuses zero-sized buffers; a one-element dummy keeps kernel signatures uniform.
    size_t bytes = std::max<size_t>(v.size(), 1) * sizeof(T);
    std::vector<T> padded = v;
    if (padded.empty()) padded.resize(1);
    return cl::Buffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, padded.data());
}
}  // namespace

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
    RenderSettings settings;
    SceneGeometry geometry;
    DeviceGeometry device_geometry;
    cl::Buffer strand_material, materials, lights;
    uint32_t light_count = 0;
    EnvironmentTables environment;
    cl::Buffer env_texels, env_marginal, env_conditional;
    cl::Buffer textures, texels;  // base colour texture headers and the shared texel array
    uint32_t texture_count = 0;
    HtCamera camera{};
    float pixel_angle = 0;  // radians per pixel at the image centre (ray footprint for --fiber-field auto)
    std::string options;
    KernelFeatures features;
    cl::Program program;
    cl::Kernel k_generate, k_closest, k_shade, k_shadow, k_resolve, k_accumulate;
    cl::Kernel k_compact_count, k_compact_scan, k_compact_scatter;
    cl::Kernel k_shadow_afs, k_resolve_afs;
    RenderStats stats;
    cl::Buffer film_buf;
    RayDump* dump = nullptr;  // --dump-rays

    // per-pass buffers, sized for max paths per pass
    size_t capacity = 0;
    cl::Buffer rays[2], ray_path[2], hits, paths, shadow_rays, shadow_contrib, occluded, counters;
    cl::Buffer stage_rays, stage_path, group_sums;  // uncompacted extension rays, per-group counts
    cl::Buffer transmittance;                        // --indirect afs: per shadow slot, rgb
    cl::Buffer afs_table;                            // --indirect afs: AFS_TT^avg(theta) per material

    Impl(ClContext& c, const Scene& scene, const RenderSettings& s) : cl(c), settings(s) {
        geometry = build_geometry(scene);
        device_geometry = upload_geometry(cl, geometry);
        std::vector<uint32_t> mat_of_strand(scene.strands.material.begin(), scene.strands.material.end());
        strand_material = device_array(cl.context(), mat_of_strand);
        const std::vector<HtMaterial> kmats = make_kernel_materials(scene.materials);
        materials = device_array(cl.context(), kmats);
        auto kl = make_kernel_lights(scene.lights);
        light_count = uint32_t(kl.size());
        lights = device_array(cl.context(), kl);
        camera = make_kernel_camera(scene.camera, s.width, s.height);
        pixel_angle = float(2.0 * std::tan(0.5 * scene.camera.yfov_deg * kPi / 180.0) / s.height);
        environment = build_environment(scene.environment);
        env_texels = device_array(cl.context(), environment.texels);
        env_marginal = device_array(cl.context(), environment.marginal);
        env_conditional = device_array(cl.context(), environment.conditional);

        const bool afs = s.indirect == RenderSettings::Indirect::Afs;
        // The render identity (render/render_identity.h) leaves the paging out: it depends on
        // the device, and paged and unpaged renders give the same bits (tested).
        stats.clamp_indirect = s.clamp_indirect;
        // Options that change the estimator, not the scene (settings of the render identity); off = undefined.
        const std::string clamp = estimator_build_options(
            stats.clamp_indirect, s.regularize_deg, s.spawn_offset == RenderSettings::SpawnOffset::Pbrt,
            s.sampler == RenderSettings::Sampler::Sobol);
        // The scene's features once (the lobe bounds are a quadrature per material).
        features = scene_features(scene, s.fiber_field, afs, s.features);
        options = kernel_build_options(features) + clamp;
        features.paging = device_geometry.paging;
        const std::string build_options = kernel_build_options(features) + clamp;
        program = cl.build("stages/wavefront.cl", build_options);
        stats.build_ms = cl.last_build_ms();
        stats.build_cached = cl.last_build_cached();
        stats.kernel_options = build_options;
        k_generate = cl::Kernel(program, "generate_camera_rays");
        k_closest = cl::Kernel(program, "intersect_closest");
        k_shade = cl::Kernel(program, "shade");
        k_shadow = cl::Kernel(program, "intersect_shadow");
        k_resolve = cl::Kernel(program, "resolve_shadows");
        k_accumulate = cl::Kernel(program, "accumulate");
        k_compact_count = cl::Kernel(program, "compact_count");
        if (afs) {
            std::vector<float> table;
            for (const HtMaterial& m : kmats) {
                const std::vector<float> t = afs_tt_table(m.eta, m.sigma_a);
                table.insert(table.end(), t.begin(), t.end());
            }
            if (table.empty()) table.assign(4 * (HT_AFS_TT_TABLE_N + 1), 0.0f);  // no buffer of size 0
            afs_table = device_array(cl.context(), table);
            k_shadow_afs = cl::Kernel(program, "intersect_shadow_afs");
            k_resolve_afs = cl::Kernel(program, "resolve_shadows_afs");
        }
        k_compact_scan = cl::Kernel(program, "compact_scan");
        k_compact_scatter = cl::Kernel(program, "compact_scatter");

        const std::vector<HtTexture> texture_headers = make_kernel_textures(scene.textures);
        const uint64_t texel_bytes = texel_buffer_size(scene.textures) * sizeof(uint32_t);
        const uint64_t scene_bytes = device_geometry.bytes + environment.texels.size() * 4 +
                                     (environment.marginal.size() + environment.conditional.size()) * 4 +
                                     texel_bytes + texture_headers.size() * sizeof(HtTexture);
        MemoryPlan plan = plan_device_memory(uint64_t(s.width) * uint64_t(s.height), scene_bytes,
                                             cl.info().max_alloc, cl.info().global_mem, s.max_device_bytes,
                                             std::max<size_t>(s.max_paths_per_pass, 1), device_geometry.paging);
        upload_textures(scene.textures, texture_headers, texel_bytes);
        allocate(plan.paths_per_pass);
    }

    // After the memory plan, so textures that cannot fit are refused before they are copied.
    void upload_textures(const std::vector<Texture>& scene_textures, const std::vector<HtTexture>& headers,
                         uint64_t texel_bytes) {
        if (cl.info().max_alloc && texel_bytes > cl.info().max_alloc)
            throw DeviceError("the scene's textures need " + format_bytes(texel_bytes) +
                              " in one buffer but the device " + cl.info().name + " allocates at most " +
                              format_bytes(cl.info().max_alloc) + " per buffer; use smaller textures");
        texture_count = uint32_t(headers.size());
        textures = device_array(cl.context(), headers);
        texels = cl::Buffer(cl.context(), CL_MEM_READ_ONLY, texel_bytes);
        uint32_t table[HT_SRGB_TABLE_SIZE];
        ht_srgb_table(table);
        cl.queue().enqueueWriteBuffer(texels, CL_TRUE, 0, sizeof table, table);
        for (size_t i = 0; i < scene_textures.size(); ++i) {
            const std::vector<uint32_t>& t = scene_textures[i].texels;
            if (!t.empty())
                cl.queue().enqueueWriteBuffer(texels, CL_TRUE, size_t(headers[i].offset) * sizeof(uint32_t),
                                              t.size() * sizeof(uint32_t), t.data());
        }
    }

    void allocate(size_t n) {
        if (injected_fault("alloc")) throw cl::Error(CL_MEM_OBJECT_ALLOCATION_FAILURE, "clCreateBuffer");
        capacity = n;
        auto& ctx = cl.context();
        size_t cap = round_up(n, kLocalSize);
        for (int i = 0; i < 2; ++i) {
            rays[i] = cl::Buffer(ctx, CL_MEM_READ_WRITE, cap * sizeof(HtRay));
            ray_path[i] = cl::Buffer(ctx, CL_MEM_READ_WRITE, cap * sizeof(uint32_t));
        }
        hits = cl::Buffer(ctx, CL_MEM_READ_WRITE, cap * sizeof(HtHit));
        paths = cl::Buffer(ctx, CL_MEM_READ_WRITE, cap * sizeof(HtPathState));
        shadow_rays = cl::Buffer(ctx, CL_MEM_READ_WRITE, cap * sizeof(HtRay));
        shadow_contrib = cl::Buffer(ctx, CL_MEM_READ_WRITE, cap * sizeof(HtShadowContrib));
        occluded = cl::Buffer(ctx, CL_MEM_READ_WRITE, cap * sizeof(uint32_t));
        counters = cl::Buffer(ctx, CL_MEM_READ_WRITE, HT_COUNTER_COUNT * sizeof(uint32_t));
        stage_rays = cl::Buffer(ctx, CL_MEM_READ_WRITE, cap * sizeof(HtRay));
        if (settings.indirect == RenderSettings::Indirect::Afs)
            transmittance = cl::Buffer(ctx, CL_MEM_READ_WRITE, cap * 4 * sizeof(float));
        stage_path = cl::Buffer(ctx, CL_MEM_READ_WRITE, cap * sizeof(uint32_t));
        group_sums = cl::Buffer(ctx, CL_MEM_READ_WRITE, (cap / kLocalSize + 1) * sizeof(uint32_t));
    }

    // ---- stages ---------------------------------------------------------------------------
    // The traversal's arrays, paged or not (kernels/geometry/pages.h); returns the next argument.
    cl_uint set_geometry_args(cl::Kernel& k) {
        cl_uint a = set_paged_args(k, 0, device_geometry.nodes);
        a = set_paged_args(k, a, device_geometry.segments);
        return set_paged_args(k, a, device_geometry.points);
    }

    void generate_camera_rays(uint32_t offset, uint32_t count, uint32_t sample) {
        k_generate.setArg(0, camera);
        k_generate.setArg(1, offset);
        k_generate.setArg(2, count);
        k_generate.setArg(3, settings.seed);
        k_generate.setArg(4, sample);
        k_generate.setArg(5, rays[0]);
        k_generate.setArg(6, ray_path[0]);
        k_generate.setArg(7, paths);
        launch(k_generate, count);
    }

    void intersect_closest(int q, uint32_t count) {
        cl_uint a = set_geometry_args(k_closest);
        k_closest.setArg(a++, rays[q]);
        k_closest.setArg(a++, hits);
        k_closest.setArg(a++, count);
        launch(k_closest, count);
    }

    void shade(int q, uint32_t count, uint32_t sample, uint32_t bounce) {
        static const uint32_t zero[HT_COUNTER_COUNT] = {0, 0, 0, 0};
        cl.queue().enqueueWriteBuffer(counters, CL_FALSE, 0, sizeof zero, zero);
        cl_uint a = 0;
        a = set_paged_args(k_shade, a, device_geometry.segments);
        a = set_paged_args(k_shade, a, device_geometry.points);
        a = set_paged_args(k_shade, a, device_geometry.triangles);
        k_shade.setArg(a++, textures);
        k_shade.setArg(a++, texture_count);
        k_shade.setArg(a++, texels);
        k_shade.setArg(a++, strand_material);
        k_shade.setArg(a++, materials);
        k_shade.setArg(a++, lights);
        k_shade.setArg(a++, light_count);
        k_shade.setArg(a++, environment.header);
        k_shade.setArg(a++, env_texels);
        k_shade.setArg(a++, env_marginal);
        k_shade.setArg(a++, env_conditional);
        k_shade.setArg(a++, rays[q]);
        k_shade.setArg(a++, hits);
        k_shade.setArg(a++, ray_path[q]);
        k_shade.setArg(a++, count);
        k_shade.setArg(a++, paths);
        k_shade.setArg(a++, shadow_rays);
        k_shade.setArg(a++, shadow_contrib);
        k_shade.setArg(a++, stage_rays);
        k_shade.setArg(a++, stage_path);
        k_shade.setArg(a++, counters);
        k_shade.setArg(a++, settings.seed);
        k_shade.setArg(a++, sample);
        k_shade.setArg(a++, bounce);
        k_shade.setArg(a++, uint32_t(settings.max_depth));
        k_shade.setArg(a++, settings.fiber_field);
        k_shade.setArg(a++, pixel_angle);
        launch(k_shade, count);
    }

    // Packs the surviving paths' extension rays into queue `out`, in slot order.
    void compact(int out, uint32_t count) {
        const uint32_t groups = uint32_t(round_up(count, kLocalSize) / kLocalSize);
        k_compact_count.setArg(0, stage_path);
        k_compact_count.setArg(1, count);
        k_compact_count.setArg(2, group_sums);
        launch(k_compact_count, count);
        k_compact_scan.setArg(0, group_sums);
        k_compact_scan.setArg(1, groups);
        k_compact_scan.setArg(2, counters);
        launch(k_compact_scan, cl::NDRange(1), cl::NDRange(1));
        k_compact_scatter.setArg(0, stage_rays);
        k_compact_scatter.setArg(1, stage_path);
        k_compact_scatter.setArg(2, count);
        k_compact_scatter.setArg(3, group_sums);
        k_compact_scatter.setArg(4, rays[out]);
        k_compact_scatter.setArg(5, ray_path[out]);
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

    void intersect_shadow(uint32_t count) {
        cl_uint a = set_geometry_args(k_shadow);
        k_shadow.setArg(a++, shadow_rays);
        k_shadow.setArg(a++, occluded);
        k_shadow.setArg(a++, count);
        launch(k_shadow, count);
    }

    void intersect_shadow_afs(uint32_t count) {
        cl_uint a = set_geometry_args(k_shadow_afs);
        k_shadow_afs.setArg(a++, strand_material);
        k_shadow_afs.setArg(a++, afs_table);
        k_shadow_afs.setArg(a++, shadow_rays);
        k_shadow_afs.setArg(a++, transmittance);
        k_shadow_afs.setArg(a++, count);
        launch(k_shadow_afs, count);
    }

    void resolve_shadows_afs(uint32_t count) {
        k_resolve_afs.setArg(0, shadow_contrib);
        k_resolve_afs.setArg(1, transmittance);
        k_resolve_afs.setArg(2, count);
        k_resolve_afs.setArg(3, paths);
        launch(k_resolve_afs, count);
    }

    void resolve_shadows(uint32_t count) {
        k_resolve.setArg(0, shadow_contrib);
        k_resolve.setArg(1, occluded);
        k_resolve.setArg(2, count);
        k_resolve.setArg(3, paths);
        launch(k_resolve, count);
    }

    void accumulate(cl::Buffer& film, uint32_t count) {
        k_accumulate.setArg(0, paths);
        k_accumulate.setArg(1, count);
        k_accumulate.setArg(2, film);
        launch(k_accumulate, count);
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

Renderer::Renderer(ClContext& cl, const Scene& scene, const RenderSettings& settings) {
    try {
        impl_ = new Impl(cl, scene, settings);
    } catch (const cl::Error& e) {
        throw DeviceError(std::string("OpenCL setup failed in ") + e.what() + ": " + cl_error_name(e.err()));
    }
}
Renderer::~Renderer() { delete impl_; }
const std::string& Renderer::kernel_options() const { return impl_->options; }
const KernelFeatures& Renderer::features() const { return impl_->features; }
const RenderStats& Renderer::stats() const { return impl_->stats; }
void Renderer::set_ray_dump(RayDump* dump) {
    impl_->dump = dump;
    if (dump) dump->bind(impl_->geometry);
}

void Renderer::upload_film(const Film& film) {
    Impl& r = *impl_;
    const size_t floats = 4 * size_t(r.settings.width) * size_t(r.settings.height);
    if (film.rgba.size() != floats)
        throw std::invalid_argument("film size does not match the render settings");
    try {
        r.film_buf = cl::Buffer(r.cl.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                                floats * sizeof(float), const_cast<float*>(film.rgba.data()));
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
    } catch (const cl::Error& e) {
        throw DeviceError(std::string("OpenCL failure reading the film: ") + cl_error_name(e.err()));
    }
}

void Renderer::render_sample(uint32_t sample) {
    Impl& r = *impl_;
    const RenderSettings& s = r.settings;
    const size_t pixels = size_t(s.width) * size_t(s.height);
    auto t0 = std::chrono::steady_clock::now();
    try {
        for (size_t offset = 0; offset < pixels; offset += r.capacity) {
            const uint32_t count = uint32_t(std::min(r.capacity, pixels - offset));
            r.generate_camera_rays(uint32_t(offset), count, sample);
            r.stats.camera_rays += count;
            int q = 0;
            uint32_t n = count;
            // max_depth scattering vertices; with an environment, the last vertex's BCSDF ray is
            // traced too, for the environment light it sees (kernels/stages/shade.cl)
            const uint32_t vertices = uint32_t(s.max_depth);
            const uint32_t traced = vertices + (r.environment.header.enabled ? 1u : 0u);
            for (uint32_t bounce = 0; n > 0 && bounce < traced; ++bounce) {
                const auto t_bounce = std::chrono::steady_clock::now();
                r.intersect_closest(q, n);
                if (r.dump) r.dump->closest(r.cl.queue(), r.rays[q], r.hits, n, bounce);
                r.shade(q, n, sample, bounce);
                if (bounce + 1 == vertices && s.indirect == RenderSettings::Indirect::Afs) {
                    r.intersect_shadow_afs(n);
                    r.resolve_shadows_afs(n);
                } else if (bounce < vertices) {
                    r.intersect_shadow(n);
                    if (r.dump) r.dump->shadow(r.cl.queue(), r.shadow_rays, r.occluded, n, bounce);
                    r.resolve_shadows(n);
                }
                if (bounce + 1 < traced) r.compact(1 - q, n);  // else no path continues
                const Impl::ShadeCounters c = r.read_counters();
                r.stats.nonfinite_caught += c.nonfinite;
                r.stats.shadow_rays += c.shadow;
                r.stats.extension_rays += c.next;
                r.stats.cut_paths += c.cut;
                if (r.stats.bounces.size() <= bounce) r.stats.bounces.resize(bounce + 1);
                BounceStats& bs = r.stats.bounces[bounce];
                bs.paths += n;
                bs.shadow_rays += c.shadow;
                bs.cut_paths += c.cut;
                // read_counters() waited for the queue: this is the bounce's wall time
                bs.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_bounce).count();
                q = 1 - q;
                n = c.next;
            }
            r.accumulate(r.film_buf, count);
        }
        r.cl.queue().finish();
    } catch (const cl::Error& e) {
        throw DeviceError(std::string("OpenCL failure in ") + e.what() + ": " + cl_error_name(e.err()));
    }
    r.stats.samples += 1;
    r.stats.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void RenderStats::add(const RenderStats& o) {
    camera_rays += o.camera_rays;
    extension_rays += o.extension_rays;
    shadow_rays += o.shadow_rays;
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
    for (int si = 0; si < s.spp; ++si) {
        render_sample(uint32_t(s.first_sample + si));
        if (progress && !progress(si + 1, s.spp)) break;
    }
    download_film(film);
    return impl_->stats;
}

}  // namespace ht
