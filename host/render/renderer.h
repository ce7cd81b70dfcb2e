// The wavefront path tracer on one OpenCL device.
#pragma once

#include "bvh/device_geometry.h"
#include "cl/device.h"
#include "core/film.h"
#include "render/features.h"
#include "render/memory_plan.h"
#include "render/prepared_scene.h"
#include "render/settings.h"
#include "render/split_choice.h"
#include "scene/scene.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ht {

// One bounce of the wavefront over all samples so far: paths shaded (= closest-hit rays traced),
// shadow rays queued, and wall seconds of its stages.
struct BounceStats {
    uint64_t paths = 0, shadow_rays = 0;
    uint64_t cut_paths = 0;  // paths this bounce ended because of max_depth
    double seconds = 0;
};

struct RenderStats {
    double seconds = 0, build_ms = 0;
    bool build_cached = false;
    uint64_t camera_rays = 0, extension_rays = 0, shadow_rays = 0;
    // --light-vertices: light rays traced (the connections to their hits are shadow rays, counted
    // in shadow_rays)
    uint64_t light_rays = 0;
    // pixel samples given the background's value without a camera ray: the pixels that see no
    // geometry (RenderSettings::skip_empty_pixels), once per sample
    uint64_t background_samples = 0;
    size_t empty_pixels = 0;  // how many pixels see no geometry (0: none, or not skipped)
    double footprint_ms = 0;  // the time taken to find them (render/pixel_footprint.h)
    // Camera rays from per-pixel candidate lists (RenderSettings::camera_lists): the lists'
    // entries (0: no lists), the pixels that traverse the tree instead, the lists' build time.
    size_t candidate_entries = 0, candidate_tree_pixels = 0;
    double candidates_ms = 0;
    // Shadow rays from the lights' lists (RenderSettings::shadow_lists): their entries
    // (0: none) and build time.
    size_t shadow_list_entries = 0;
    double shadow_lists_ms = 0;
    // Path rays from the uniform grid (RenderSettings::path_rays): its cells and entries (0: the
    // tree) and build time.
    size_t path_grid_cells = 0, path_grid_occupied = 0, path_grid_entries = 0;
    double path_grid_ms = 0;
    // The lists made but left on the host, because the render fits the device only without them
    // (the rays then traverse the tree: the same hits).
    bool camera_lists_dropped = false, shadow_lists_dropped = false;
    bool path_grid_dropped = false;  // --path-rays auto's grid exceeds the device's allocation: the tree
    // camera rays x --first-hit-splits: the paths of the estimate, each continuation one of them
    uint64_t paths = 0;
    uint64_t nonfinite_caught = 0;  // NaN/Inf values zeroed by the kernels
    // Paths cut by max_depth: with an environment, those whose last vertex's BCSDF ray met a
    // surface; without one, those that scattered at their last allowed vertex (an upper bound
    // on the paths that would have gone on).
    uint64_t cut_paths = 0;
    int samples = 0;
    std::string kernel_options;
    float clamp_indirect = 0.0f;  // the cap in effect (0: none)
    float light_guiding = 0.0f;   // the share of continuations guided towards the lights (0: none)
    // With RenderSettings::profile_stages: seconds per stage kernel (the queue is drained after
    // every launch, which costs some overlap, so only the proportions are meaningful).
    std::vector<std::pair<std::string, double>> stage_seconds;
    std::vector<BounceStats> bounces;  // wavefront throughput per bounce

    // Adds another device's statistics (counts, times and per-bounce rows).
    void add(const RenderStats& o);
};

// Called after each finished sample pass with (samples done, samples total); returning false
// stops the render after that sample (time limits, interrupts).
using ProgressFn = std::function<bool(int, int)>;

class RayDump;

// The render program's build options: the scene's features and estimator values, on geometry
// cut into device buffers as `paging` (which depends on the device).
std::string render_program_options(KernelFeatures features, const std::string& estimator_options,
                                   const GeometryPaging& paging);

// Starts compiling the render program on `cl` in the background (ClContext::prefetch) from a
// recipe (prepare_scene's RecipeReady), so the compile overlaps the BVH build and the upload.
// It assumes unpaged geometry and does nothing for scenes whose geometry could approach the
// device's allocation limit; the Renderer builds whatever the upload needs either way.
void prefetch_render_program(ClContext& cl, const PreparedScene& recipe, const Scene& scene);
// The same for the program of the stages that read camera and shadow lists (kernels/stages/lists.cl),
// from prepare_scene's lists_ready: compiled only for renders that make lists.
void prefetch_lists_program(ClContext& cl, const PreparedScene& recipe, const Scene& scene);

class Renderer {
public:
    // Uploads `prepared` (which must outlive the renderer) and builds the kernels for this device.
    // geometry: how its BVH arrays reach the device (bvh/device_geometry.h).  Shared makes them
    // the buffers on a CPU device; renderers that use one prepared scene at the same time pass
    // Copy, as OpenCL leaves several buffers made on one host region undefined.
    Renderer(ClContext& cl, const PreparedScene& prepared, GeometryMemory geometry = GeometryMemory::Shared);
    // The same for a scene prepared for this renderer alone (tests, single-device tools).
    Renderer(ClContext& cl, const Scene& scene, const RenderSettings& settings);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Renders samples [settings.first_sample, settings.first_sample + settings.spp) into film,
    // which may already hold earlier samples (resume).  Stops early when progress says so.
    RenderStats render(Film& film, const ProgressFn& progress = {});

    // The same, one step at a time, for callers that checkpoint between samples:
    void upload_film(const Film& film);
    void render_sample(uint32_t sample);  // one sample of every pixel, finished on return
    // Samples first .. first + count - 1 of every pixel, finished on return: the same film as
    // count render_sample calls, with up to samples_per_pass() of them in each pass.
    void render_samples(uint32_t first, uint32_t count);
    // How many samples a pass renders now (--samples-per-pass, when a pass holds every traced pixel
    // that many times; else 1): callers that stop between samples step by it.
    int samples_per_pass() const;
    void download_film(Film& film);
    // The pixels the next render_sample calls render (indices y * width + x, ascending); empty:
    // every pixel.  render --target-error narrows it to the tiles still above the target; the
    // others keep their film values untouched.
    void set_pixels(const std::vector<uint32_t>& pixels);
    const RenderStats& stats() const;

    // --first-hit-splits: the continuations per camera sample in use; 0 while auto has not yet
    // chosen (the first render_sample chooses when nobody did before).
    int first_hit_splits() const;
    // auto: runs the pilot (render/split_choice.h) and uses its choice from now on; it may be run
    // again and chooses the same.  Otherwise returns the fixed N.  Throws DeviceError.
    SplitChoice choose_first_hit_splits();
    // Uses N continuations from now on (another device's choice, so that all devices agree).
    void set_first_hit_splits(int n);

    const std::string& kernel_options() const;
    // How the scene's geometry was cut into device buffers on this device.
    // What the render program was compiled with (paging included: it depends on the device).
    const KernelFeatures& features() const;

    // --dump-rays: every later render copies its traced rays into `dump` (render/ray_dump.h);
    // nullptr stops.  The dump must outlive the renders.
    void set_ray_dump(RayDump* dump);

private:
    struct Impl;
    Impl* impl_;
};

}  // namespace ht
