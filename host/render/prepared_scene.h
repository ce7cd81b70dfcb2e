// A scene made ready for the kernels, once per render on the host: the BVH, the kernels' camera,
// lights, materials, texture headers, environment tables, AFS tables and the features to compile.
// Every device's Renderer uploads and launches from one PreparedScene (render/renderer.h), and the
// render identity (render/render_identity.h) hashes its bytes, so what a checkpoint or a
// render-farm part is keyed on is exactly what the devices were given.
#pragma once

#include "bvh/bvh.h"
#include "render/path_grid.h"
#include "render/environment.h"
#include "render/features.h"
#include "render/candidate_lists.h"
#include "render/pixel_footprint.h"
#include "render/settings.h"
#include "render/shadow_lists.h"
#include "scene/scene.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ht {

struct PreparedScene {
    RenderSettings settings;
    SceneGeometry geometry;                  // points, leaf segments, BVH nodes, triangle shading
    std::vector<uint32_t> strand_material;   // material index per strand
    std::vector<HtMaterial> materials;       // after every override, converted (make_kernel_materials)
    std::vector<HtLight> lights;
    HtCamera camera{};
    float pixel_angle = 0;                   // radians per pixel at the image centre (--fiber-field auto)
    EnvironmentTables environment;
    std::vector<HtTexture> texture_headers;  // offsets into the shared texel buffer
    const std::vector<Texture>* textures = nullptr;  // the scene's texels, copied at upload
    uint64_t texel_bytes = 0;                // the shared texel buffer: sRGB table + every texture
    std::vector<float> afs_table;            // --indirect afs: AFS_TT^avg(theta) per material
    std::vector<float> dual_table;           // --indirect dual: kernels/fiber/dual.h's rows per material
    KernelFeatures features;                 // what the scene needs (geometry unpaged)
    // The pixels that see no geometry and those that may (render/pixel_footprint.h), found when
    // the render skips the former (RenderSettings::skip_empty_pixels, and neither --aovs nor an
    // environment map); both empty otherwise.  footprint_ms: the time it took.
    PixelFootprint footprint;
    double footprint_ms = 0;
    // Each pixel's candidates for its camera rays (RenderSettings::camera_lists; disabled
    // otherwise, or when the projection is unbounded), and the time they took.
    PixelCandidates candidates;
    double candidates_ms = 0;
    // The lights' shadow lists (RenderSettings::shadow_lists) and their time.
    ShadowLists shadow_lists;
    double shadow_lists_ms = 0;
    // The path rays' grid (RenderSettings::path_rays; features[PATH_GRID] says whether there is
    // one, decided with the recipe) and its time.
    PathGrid path_grid;
    double path_grid_ms = 0;
    std::string estimator_options;           // the estimator's -D values (clamp, sampler, ...)
    // --light-vertices (settings.light_vertices > 0): the sphere around every point of the geometry
    // (strands and triangles, inflated by their radii) that the light rays aim at, and their count
    // per camera sample; first_sample is the renderer's to set.
    HtLightVertices light_vertices{};

    // Device bytes of everything but the geometry (textures, environment tables, candidate lists).
    uint64_t extra_scene_bytes() const;
};

// Why --light-vertices (settings.light_vertices > 0) cannot render `scene` with these settings, or
// "" when it can: it needs a light that starts light rays (a point, spot or directional light;
// kernels/integrator/light_vertices.h ht_light_ray), and neither --indirect afs or dual (their
// last bounce stands for that light already) nor --aovs (a connection is not split by lobe or
// bounce).  The command line reports it as a usage error, prepare_scene throws it.
std::string light_vertices_refusal(const Scene& scene, const RenderSettings& settings);

// Called once the kernels' recipe (features, estimator_options) is known and before the BVH is
// built, which takes most of the preparation: program builds started there overlap it
// (render/renderer.h prefetch_render_program).  Only those two fields and `settings` are set.
using RecipeReady = std::function<void(const PreparedScene& recipe)>;

// Builds everything above from `scene` (after the command line's overrides; it must outlive the
// result, whose `textures` points into it).  Throws SceneError for an unreadable environment map.
// lists_ready, with the scene prepared so far (the recipe's fields among them), once the render has
// chosen to make camera or shadow lists and before it makes them, at most once: the program of the
// stages that read them is started there (render/renderer.h prefetch_lists_program), so a render
// without lists never compiles it.
PreparedScene prepare_scene(const Scene& scene, const RenderSettings& settings,
                            const RecipeReady& recipe_ready = {}, const RecipeReady& lists_ready = {});

}  // namespace ht
