// What a render is asked to do, beyond the scene: image size, samples, depth and the estimator's
// options.  Everything here but the pass size, memory limit and profiling shapes the image and is
// part of the render identity (render/render_identity.h).
#pragma once

#include "bvh/bvh.h"
#include "render/features.h"

#include "kernels/types.h"

#include <cstddef>
#include <cstdint>

namespace ht {

// --first-hit-splits and --first-hit-light-samples at most: a pixel's path slots then fit in one
// work-group, the smallest pass the memory plan admits, and sample * N stays far below 2^32
// (kernels/rng.h).
constexpr int kMaxFirstHitSplits = 64;
// RenderSettings::first_hit_splits for --first-hit-splits auto (render/split_choice.h).
constexpr int kAutoFirstHitSplits = 0;

// --light-threshold's range (kernels/integrator/roulette.h): above 1 every estimate of a white
// fibre would be played for.
constexpr double kMinLightThreshold = 1e-6, kMaxLightThreshold = 1;

// --light-guiding's range (kernels/integrator/light_guide.h): the share of a fibre vertex's
// continuations drawn towards the lights; 1 would leave directions no light lies in unsampled.
constexpr double kMinLightGuiding = 1e-3, kMaxLightGuiding = 0.9;

// --light-vertices' range: light rays per camera sample (their Sobol' indices, sample x count,
// must stay below 2^32 for a million samples).
constexpr uint32_t kMaxLightVertices = 4096;
// The light rays per camera sample in effect: none where no vertex has a connection to make
// (depth 1: the first vertex's continuation is not traced).
inline uint32_t effective_light_vertices(uint32_t setting, int max_depth) { return max_depth >= 2 ? setting : 0u; }
// RenderSettings::bvh_oriented for --bvh-oriented auto: BvhOptions' oriented nodes when the render
// takes at least kOrientedVerticesPerSegment path vertices per segment (width x height x spp x max
// depth), else axis-aligned ones.  Their build costs about 0.2 us per segment more, cold (the
// anchor's 3.2M-segment head: +0.6-0.9 s), and their traversal wins it back from about 3.3
// vertices per segment on the head; scenes where they win nothing lose only that build
// (host/bvh/NOTES.md "Oriented nodes by default").
constexpr float kAutoOriented = -1.0f;
constexpr double kOrientedVerticesPerSegment = 4;
// The ratio in effect for `setting`, a render of `vertices` path vertices at most over `segments`
// segments; oriented splits need oriented nodes, so auto takes them with splits.
inline float effective_bvh_oriented(float setting, float splits, double vertices, size_t segments) {
    if (setting != kAutoOriented) return setting;
    return splits > 0 || vertices >= kOrientedVerticesPerSegment * double(segments) ? BvhOptions().obb_ratio : 0.0f;
}

// RenderSettings::light_guiding for --light-guiding auto, and the share auto takes.
constexpr float kAutoLightGuiding = -1.0f, kDefaultLightGuiding = 0.2f;

// The share of continuations guided in a scene with or without lights and an environment that
// gives light: none without lights; auto guides a scene lit by its lights alone.  An environment's
// light arrives from every direction the guide does not aim at, and guided weights spread (1 / (F
// r + 1 - F) per vertex): in the white furnace of a dense lock (tests/render/furnace_test.cpp)
// guiding towards a light that gives nothing put single pixels at 0.4-1.7 of the truth at 16 spp.
inline float effective_light_guiding(float setting, bool has_lights, bool environment_gives_light) {
    if (!has_lights) return 0.0f;
    if (setting < 0) return environment_gives_light ? 0.0f : kDefaultLightGuiding;
    return setting;
}

// Whether --light-pick importance has a choice to make among `lights` lights: two or more, and no
// more than the kernels' pick reads (HT_LIGHT_PICK_MAX); otherwise every pick is uniform.
inline bool light_pick_chooses(size_t lights) { return lights >= 2 && lights <= HT_LIGHT_PICK_MAX; }

// RenderSettings::samples_per_pass by default: measured in docs/PERFORMANCE.md section 8
// "Several samples per pass"; and the most the command line accepts.
constexpr int kDefaultSamplesPerPass = 8;
constexpr int kMaxSamplesPerPass = 64;

struct RenderSettings {
    int width = 512, height = 512;
    int spp = 16;
    uint32_t seed = 1;
    int max_depth = 1;        // 1 = direct light only
    uint32_t fiber_field = 0; // HT_FIELD_MATERIAL | NEAR | FAR | AUTO
    // Light beyond the last traced bounce: none, or the paper's averaged attenuation (AFS):
    // the last bounce's shadow rays pass through hair with AFS_TT^avg per fibre crossed; or dual
    // scattering (depth 1: its shadow rays gather the forward transmittance and spread through
    // hair, plus precomputed local back-scattering; kernels/fiber/dual.h).
    enum class Indirect { Exact, Afs, Dual } indirect = Indirect::Exact;
    int first_sample = 0;     // render samples [first_sample, first_sample + spp)
    size_t max_paths_per_pass = 1u << 20;  // bounds device memory for big images
    // --samples-per-pass: how many consecutive samples of each traced pixel one pass renders when
    // all of them fit, so that a pixel's samples are neighbouring work-items (its candidate list
    // and fibres in cache) and each stage is launched once for them all; the film is the same bits
    // for any value (kernels/stages/accumulate.cl).  1: a pass per sample.
    int samples_per_pass = kDefaultSamplesPerPass;
    uint64_t max_device_bytes = 0;         // --max-memory (0: the device's global memory)
    bool profile_stages = false;           // time each stage kernel (drains the queue after each)
    // Cap on each indirect sample's contribution (largest channel; 0: none), compiled into shade.
    float clamp_indirect = 0.0f;
    // Path regularisation: minimum lobe width (degrees) at hair reached after a scattering (0: off).
    float regularize_deg = 0.0f;
    // --light-threshold: next-event estimates whose weight without the light is below it trace
    // their shadow ray by Russian roulette (kernels/integrator/roulette.h); 0 here (off), the
    // command line's default is chosen by measurement (docs/PERFORMANCE.md §8).
    float light_threshold = 0.0f;
    // --light-guiding: the share of a fibre vertex's continuations drawn from a lobe around the
    // direction to a light instead of from the BCSDF, weighted by the mixture's density
    // (kernels/integrator/light_guide.h); 0 here (off), the command line's default is chosen by
    // measurement (docs/PERFORMANCE.md §8).  kAutoLightGuiding: effective_light_guiding decides.
    float light_guiding = 0.0f;
    // --light-vertices N: light rays per camera sample from the scene's point, spot and directional
    // lights, taking turns, whose first fibre hits each fibre vertex below the last connects to,
    // sharing those paths with its continuations by MIS (kernels/integrator/light_vertices.h); 0: none.
    uint32_t light_vertices = 0;
    // How a single next-event estimate chooses among two or more lights: uniformly (here), or half
    // by what each light delivers unshadowed at the shading point times how squarely it faces the
    // fibre or surface there, half evenly over the lights that reach it (kernels/lights.h
    // ht_pick_light; up to HT_LIGHT_PICK_MAX lights, uniform above).  The command line's default is
    // chosen by measurement (docs/PERFORMANCE.md §8).
    enum class LightPick { Uniform, Importance } light_pick = LightPick::Uniform;
    // Random numbers: Owen-scrambled Sobol' or independent hashing (kernels/rng.h).
    enum class Sampler { Sobol, Independent } sampler = Sampler::Sobol;
    // Continuations per camera path from its first vertex, each with 1/N of the weight, while the
    // camera ray, its hit and its next-event estimate are done once (kernels/stages/shade.cl).
    // 1 here, the plain estimator; kAutoFirstHitSplits: chosen per scene by a pilot render
    // (render/split_choice.h), the command line's default (docs/PERFORMANCE.md §8).
    int first_hit_splits = 1;
    // Next-event estimates at that first vertex, each with 1/M of the weight and its own stratum
    // of the light pick (1 here; the command line's auto is one per light).
    int first_hit_light_samples = 1;
    // Where rays leaving a fibre start: just outside the capsule (the default), or offset as
    // pbrt-v4 offsets its curves' rays (a diagnostic for comparisons with pbrt, docs/ESTIMATOR.md).
    enum class SpawnOffset { Capsule, Pbrt } spawn_offset = SpawnOffset::Capsule;
    FeatureMode features = FeatureMode::Scene;  // --features: what is compiled in
    // --aovs: record the output values of kernels/aovs.h (the beauty is the same bits either way).
    bool aovs = false;
    // --empty-pixels skip: pixels whose camera rays provably miss every primitive
    // (render/pixel_footprint.h) get the background's value without being traced -- the same
    // bits as tracing them.  Off: every pixel is traced (for A/B measurements).
    bool skip_empty_pixels = true;
    // Rays of one kind (camera rays, shadow rays toward a directional light) find their closest
    // hit or a blocker from lists made for them (Lists), by the tree (Tree), or from lists when
    // the render traces enough of them to pay for the lists (Auto).  The same answers either way.
    enum class ListChoice { Auto, Lists, Tree };
    // --camera-rays: a camera ray tests its pixel's candidate list, nearest first, instead of
    // traversing the tree (render/candidate_lists.h pixel_candidates).  Auto: lists when spp
    // times the image's pixels reaches kCameraListRaysPerPrimitive per primitive.
    ListChoice camera_lists = ListChoice::Auto;
    uint32_t camera_list_cap = 0;  // a pixel's longest list (0: kMaxCandidatesPerPixel); tests set less
    // --shadow-rays lists: shadow rays toward a directional light test the list of their cell in a
    // grid across the light's direction, toward a point or spot light outside the hair that of
    // their cell in the image seen from the light (render/shadow_lists.h) -- the same answers.  Tree: every
    // shadow ray traverses the tree.  Auto: lists when the first-vertex shadow rays that would use
    // them, spp times the pixels that see geometry times list_shadow_rays_per_path, reach
    // kShadowListRaysPerEntry per entry the lists would hold (estimate_shadow_list_entries; below
    // that, making them costs more than they save).
    using ShadowLists = ListChoice;
    ShadowLists shadow_lists = ShadowLists::Auto;
    // --path-rays: the closest hits of the path rays (every ray after the camera's) from a uniform
    // grid of capsule lists (Grid; render/path_grid.h) or by the tree from the node of the path's last
    // hit (Tree); Auto: the grid when the render traces enough path rays per segment to pay for
    // making it (wants_path_grid, render/prepared_scene.cpp), enough of its cells hold capsules
    // (kPathGridMinOccupiedShare) and its arrays fit the device's buffers
    // (Renderer, keep_path_grid_if_it_fits).  The same answers either way; a scene with triangles
    // keeps the tree (the grid lists capsules only).
    enum class PathRays { Auto, Grid, Tree };
    PathRays path_rays = PathRays::Auto;

    // --target-error: after adaptive_min_spp samples everywhere, further chunks only for the
    // tiles whose relative error estimate exceeds it (render/adaptive.h); 0: every pixel gets
    // every sample.  The films then carry their even halves (core/film.h).
    float target_error = 0.0f;
    int adaptive_min_spp = 0;
    // --bvh-oriented: BvhOptions::obb_ratio of the scene's BVH (0: axis-aligned nodes only;
    // kAutoOriented: effective_bvh_oriented decides).  Not identity: every tree gives the same
    // hits, bit for bit (a tie at equal t goes to the higher segment id whatever the visiting
    // order, kernels/geometry/bvh_traverse.h ht_hit_precedes).
    float bvh_oriented = kAutoOriented;
    // --bvh-oriented-splits: BvhOptions::obb_split (0: axis-aligned splits only); needs oriented
    // nodes (auto then takes them).  Not identity for the same reason.
    float bvh_oriented_splits = 0.0f;
};

}  // namespace ht
