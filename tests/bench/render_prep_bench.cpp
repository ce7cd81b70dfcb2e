// Host work done once per render before the first sample (render/prepared_scene.cpp), on pbrt's
// lock at 256 x 256 (scenes/pbrt_strand.gltf; `tools/pbrt-compare` writes its .bin): the
// projection, the empty pixels, the camera's candidate lists and the light's shadow lists.
// converge counts these in its seconds, so at depth 1 they are a share of the time to an error.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "render/candidate_lists.h"
#include "render/pixel_footprint.h"
#include "render/primitive_images.h"
#include "render/scene_upload.h"
#include "render/shadow_lists.h"
#include "scene/scene.h"

using namespace ht;

namespace {

struct LockScene {
    bool ok = false;
    SceneGeometry geometry;
    HtCamera camera{};
    std::vector<HtLight> lights;
};

const LockScene& lock_scene() {
    static const LockScene s = [] {
        LockScene l;
        const std::string path = std::string(HT_SOURCE_DIR) + "/scenes/pbrt_strand.gltf";
        if (!std::filesystem::exists(std::string(HT_SOURCE_DIR) + "/scenes/pbrt_strand.bin")) return l;
        const Scene scene = load_scene(path);
        l.geometry = build_geometry(scene);
        l.camera = make_kernel_camera(scene.camera, 256, 256);
        l.lights = make_kernel_lights(scene.lights);
        l.ok = true;
        return l;
    }();
    return s;
}

bool skip_without_lock(benchmark::State& state) {
    if (lock_scene().ok) return false;
    state.SkipWithError("scenes/pbrt_strand.bin missing: run tools/pbrt-compare once");
    return true;
}

void BM_ProjectPrimitives(benchmark::State& state) {
    if (skip_without_lock(state)) return;
    for (auto _ : state) benchmark::DoNotOptimize(project_primitives(lock_scene().camera, lock_scene().geometry));
}
BENCHMARK(BM_ProjectPrimitives)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PixelFootprint(benchmark::State& state) {
    if (skip_without_lock(state)) return;
    const ProjectedPrimitives p = project_primitives(lock_scene().camera, lock_scene().geometry);
    for (auto _ : state) benchmark::DoNotOptimize(pixel_footprint(p));
}
BENCHMARK(BM_PixelFootprint)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PixelCandidates(benchmark::State& state) {
    if (skip_without_lock(state)) return;
    const ProjectedPrimitives p = project_primitives(lock_scene().camera, lock_scene().geometry);
    for (auto _ : state) benchmark::DoNotOptimize(pixel_candidates(p));
}
BENCHMARK(BM_PixelCandidates)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ShadowLists(benchmark::State& state) {
    if (skip_without_lock(state)) return;
    for (auto _ : state) benchmark::DoNotOptimize(build_shadow_lists(lock_scene().geometry, lock_scene().lights));
}
BENCHMARK(BM_ShadowLists)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
