#include "render/prepared_scene.h"

#include "bvh/start_nodes.h"

#include "core/constants.h"
#include "fiber/afs_quadrature.h"
#include "fiber/dual_scattering.h"
#include "kernels/fiber/afs.h"
#include "render/primitive_images.h"
#include "render/scene_upload.h"

#include <algorithm>
#include <stdexcept>
#include <chrono>
#include <cmath>

namespace ht {

uint64_t PreparedScene::extra_scene_bytes() const {
    return environment.texels.size() * sizeof(float) +
           (environment.marginal.size() + environment.conditional.size()) * sizeof(float) + texel_bytes +
           texture_headers.size() * sizeof(HtTexture) + (afs_table.size() + dual_table.size()) * sizeof(float) +
           candidates.bytes() + shadow_lists.bytes() + path_grid.bytes();
}

namespace {

// RenderSettings::path_rays: a grid for the path rays of a hair-only scene whose render traces
// them, when asked, or (auto) when the path rays the render may trace reach kPathGridRaysPerSegment
// per segment and the scene has at most kPathGridAutoMaxSegments (and, once made, the grid's cells
// are occupied enough: prepare_scene; docs/PERFORMANCE.md section 1
// "Path rays from a uniform grid").
bool wants_path_grid(const RenderSettings& s, const Scene& scene, const KernelFeatures& f) {
    using Mode = RenderSettings::PathRays;
    const size_t segments = scene.strands.segment_count();
    if (s.path_rays == Mode::Tree || f[Feature::MESHES] || segments == 0 || s.max_depth < 2) return false;
    if (s.path_rays == Mode::Grid) return true;
    if (segments > kPathGridAutoMaxSegments) return false;
    const double rays = double(s.spp) * double(s.width) * double(s.height) * double(s.max_depth - 1);
    return rays >= kPathGridRaysPerSegment * double(segments);
}

// RenderSettings::shadow_lists: whether the lists will save more than they cost: the shadow rays
// that would use them against the entries they would hold (render/shadow_lists.h; measured in
// docs/PERFORMANCE.md section 8 "Shadow rays from per-cell lists").
bool wants_shadow_lists(const RenderSettings& s, const PreparedScene& p) {
    using Mode = RenderSettings::ShadowLists;
    if (s.shadow_lists != Mode::Auto) return s.shadow_lists == Mode::Lists;
    size_t grids = 0;
    for (const HtLight& l : p.lights) grids += casts_shadow_lists(l);
    grids = std::min(grids, kMaxShadowGrids);
    const double pixels = p.footprint.seen.empty() && p.footprint.empty.empty() ? double(s.width) * s.height
                                                                                  : double(p.footprint.seen.size());
    const double rays = double(s.spp) * pixels * list_shadow_rays_per_path(s), per_entry = kShadowListRaysPerEntry;
    // every primitive is listed in a cell of every grid at least: fewer rays need no estimate
    if (grids == 0 || rays <= 0 || rays < per_entry * double(p.geometry.segments.size()) * double(grids)) return false;
    // none when no light can have a grid (a point light among the hair)
    const double entries = estimate_shadow_list_entries(p.geometry, p.lights);
    return entries > 0 && rays >= per_entry * entries;
}

// RenderSettings::camera_lists: whether the lists will save more than they cost (decided before
// the projection, so by the image's pixels, render/candidate_lists.h kCameraListRaysPerPrimitive).
bool wants_camera_lists(const RenderSettings& s, const SceneGeometry& geometry) {
    using Mode = RenderSettings::ListChoice;
    if (s.camera_lists != Mode::Auto) return s.camera_lists == Mode::Lists;
    return double(s.spp) * double(s.width) * double(s.height) >=
           kCameraListRaysPerPrimitive * double(geometry.segments.size());
}

}  // namespace

namespace {

// PreparedScene::light_vertices for `count` light rays per camera sample.
HtLightVertices light_vertex_sphere(const SceneGeometry& geometry, uint32_t count) {
    float lo[3] = {HUGE_VALF, HUGE_VALF, HUGE_VALF}, hi[3] = {-HUGE_VALF, -HUGE_VALF, -HUGE_VALF};
    for (const HtPoint& q : geometry.points) {
        const float c[3] = {q.x, q.y, q.z};
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], c[a] - q.r);
            hi[a] = std::max(hi[a], c[a] + q.r);
        }
    }
    HtLightVertices lv{};
    double r2 = 0;
    for (int a = 0; a < 3; ++a) {
        lv.disc[a] = 0.5f * (lo[a] + hi[a]);
        r2 += 0.25 * double(hi[a] - lo[a]) * double(hi[a] - lo[a]);
    }
    lv.disc[3] = float(std::sqrt(r2) * 1.001 + 1e-6);
    lv.count = count;
    return lv;
}

}  // namespace

std::string light_vertices_refusal(const Scene& scene, const RenderSettings& s) {
    if (s.light_vertices == 0) return "";
    if (s.indirect != RenderSettings::Indirect::Exact)
        return "--light-vertices connects path vertices to lit fibres; --indirect afs and dual stand for that light at "
               "the first hit instead: render without one of them";
    if (s.aovs) return "--aovs cannot split --light-vertices' connections by lobe or bounce; render without one of them";
    if (std::none_of(scene.lights.begin(), scene.lights.end(), [](const Light& l) { return l.type != LightType::Sphere; }))
        return "--light-vertices starts light rays from point, spot and directional lights; the scene has none";
    return "";
}

PreparedScene prepare_scene(const Scene& scene, const RenderSettings& s, const RecipeReady& recipe_ready,
                            const RecipeReady& lists_ready) {
    PreparedScene p;
    p.settings = s;
    p.settings.light_guiding = effective_light_guiding(s.light_guiding, !scene.lights.empty(), scene.environment.enabled());
    // before anything starts (the recipe's callback may start compiling)
    const std::string refusal = light_vertices_refusal(scene, s);
    if (!refusal.empty()) throw std::invalid_argument(refusal);
    p.settings.light_vertices = effective_light_vertices(s.light_vertices, s.max_depth);
    const bool afs = s.indirect == RenderSettings::Indirect::Afs;
    // The lobe bounds are a quadrature per material: once per render, not per device.
    p.features = scene_features(scene, s.fiber_field, afs, s.features);
    p.features[Feature::AOVS] = s.aovs;
    p.features[Feature::INDIRECT_DUAL] = s.indirect == RenderSettings::Indirect::Dual;
    p.features[Feature::PATH_GRID] = wants_path_grid(s, scene, p.features);
    p.estimator_options = estimator_build_options(s.clamp_indirect, s.regularize_deg, s.light_threshold,
                                                  s.spawn_offset == RenderSettings::SpawnOffset::Pbrt,
                                                  s.sampler == RenderSettings::Sampler::Sobol,
                                                  s.light_pick == RenderSettings::LightPick::Importance &&
                                                      light_pick_chooses(scene.lights.size()),
                                                  p.settings.light_guiding, p.settings.light_vertices > 0);
    if (recipe_ready) recipe_ready(p);
    BvhOptions bvh;
    bvh.obb_ratio = effective_bvh_oriented(s.bvh_oriented, s.bvh_oriented_splits,
                                           double(s.width) * s.height * s.spp * std::max(1, s.max_depth),
                                           scene.strands.segment_count());
    bvh.obb_split = s.bvh_oriented_splits;
    p.geometry = build_geometry(scene, bvh);
    if (p.features[Feature::PATH_GRID]) {
        const auto t0 = std::chrono::steady_clock::now();
        p.path_grid = build_path_grid(p.geometry);
        p.path_grid_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        // auto's second look, at the grid made: hair in clumps far apart shares one box, whose cells
        // (sized by the box) are too coarse for the hair in them (kPathGridMinOccupiedShare), and a
        // grid past 32-bit offsets is not made; the tree then (the program the recipe started
        // compiling with the grid goes unused)
        if (s.path_rays == RenderSettings::PathRays::Auto &&
            (p.path_grid.empty() || double(p.path_grid.occupied_cells()) < kPathGridMinOccupiedShare * double(p.path_grid.cells()))) {
            p.path_grid = PathGrid{};
            p.features[Feature::PATH_GRID] = false;
        }
    }
    p.strand_material.assign(scene.strands.material.begin(), scene.strands.material.end());
    p.materials = make_kernel_materials(scene.materials);
    p.lights = make_kernel_lights(scene.lights);
    p.camera = make_kernel_camera(scene.camera, s.width, s.height);
    p.pixel_angle = float(2.0 * std::tan(0.5 * scene.camera.yfov_deg * kPi / 180.0) / s.height);
    p.environment = build_environment(scene.environment);
    p.texture_headers = make_kernel_textures(scene.textures);
    p.textures = &scene.textures;
    p.texel_bytes = texel_buffer_size(scene.textures) * sizeof(uint32_t);
    if (p.settings.light_vertices > 0) p.light_vertices = light_vertex_sphere(p.geometry, p.settings.light_vertices);
    const HtEnvironment& env = p.environment.header;
    const bool skip_empty = s.skip_empty_pixels && !s.aovs && !(env.enabled && env.has_map);
    // which primitive begins at each point: made once for the camera's projection and the
    // lights' alike, by whichever comes first
    PrimitiveStarts starts;
    const bool camera_lists = wants_camera_lists(s, p.geometry);
    bool lists_announced = false;
    const auto announce_lists = [&] {
        if (lists_ready && !lists_announced) lists_ready(p);
        lists_announced = true;
    };
    if (camera_lists) announce_lists();
    if (skip_empty || camera_lists) {
        const auto t0 = std::chrono::steady_clock::now();
        starts = primitive_starts(p.geometry);
        const ProjectedPrimitives projected = project_primitives(p.camera, p.geometry, &starts);
        const auto t1 = std::chrono::steady_clock::now();
        if (camera_lists) {
            p.candidates = pixel_candidates(projected, s.camera_list_cap ? s.camera_list_cap : kMaxCandidatesPerPixel);
            if (p.candidates.enabled) p.candidates.leaf_node = leaf_entry_nodes(p.geometry);
        }
        const auto t2 = std::chrono::steady_clock::now();
        // the lists, when there are some, say which pixels are empty more tightly and at once
        if (skip_empty) p.footprint = p.candidates.enabled ? pixel_footprint(p.candidates) : pixel_footprint(projected);
        const auto t3 = std::chrono::steady_clock::now();
        const auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
        // the projection is the footprint's when both are made
        p.footprint_ms = skip_empty ? ms(t0, t1) + ms(t2, t3) : 0.0;
        p.candidates_ms = ms(t1, t2) + (skip_empty ? 0.0 : ms(t0, t1));
    }
    if (wants_shadow_lists(s, p)) {
        announce_lists();
        const auto t0 = std::chrono::steady_clock::now();
        if (starts.primitive.empty()) starts = primitive_starts(p.geometry);
        p.shadow_lists = build_shadow_lists(p.geometry, p.lights, kShadowCellRadii, &starts);
        p.shadow_lists_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    }

    if (afs) {
        for (const HtMaterial& m : p.materials) {
            const std::vector<float> t = afs_tt_table(m.eta, m.sigma_a);
            p.afs_table.insert(p.afs_table.end(), t.begin(), t.end());
        }
        if (p.afs_table.empty()) p.afs_table.assign(4 * (HT_AFS_TT_TABLE_N + 1), 0.0f);  // no buffer of size 0
    }
    if (p.features[Feature::INDIRECT_DUAL]) {
        for (const HtMaterial& m : p.materials) {
            const std::vector<float> t = dual_table(m);
            p.dual_table.insert(p.dual_table.end(), t.begin(), t.end());
        }
    }
    return p;
}

}  // namespace ht
