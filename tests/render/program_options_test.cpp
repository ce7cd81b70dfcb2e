// `hairtrace bench` must measure the traversal the renderer runs: the intersection program it
// builds (host/bvh/device_geometry.h DeviceTracer) and the render program must agree on every
// option that changes the traversal code (the OpenCL compiler flags, meshes in or out, paging).
// The Renderer also collects the builds it started before the BVH instead of compiling again.
#include <gtest/gtest.h>

#include "bvh/bvh.h"
#include "bvh/device_geometry.h"
#include "cl/device.h"
#include "render/renderer.h"
#include "scene/scene.h"

#include <set>
#include <sstream>
#include <string>

using namespace ht;

namespace {

// The tokens of a build-option string that the traversal code reads.
std::set<std::string> traversal_options(const std::string& options) {
    std::set<std::string> out;
    std::istringstream in(options);
    std::string tok;
    while (in >> tok)
        if (tok.rfind("-cl-", 0) == 0 || tok.rfind("-DHT_FEATURE_MESHES=", 0) == 0 ||
            tok.rfind("-DHT_GEOMETRY_PAGE", 0) == 0)
            out.insert(tok);
    return out;
}

void expect_same_traversal(const std::string& source) {
    static ClContext cl;
    Scene scene = load_scene(source);
    ensure_camera_and_light(scene);
    RenderSettings rs;
    rs.width = rs.height = 8;
    rs.spp = 1;
    const int compiles_before = cl.compiles();
    Renderer renderer(cl, scene, rs);
    // The render program's trace and shade builds, each once: the builds started before the BVH
    // (prefetch_render_program) had the options the Renderer asks for.
    EXPECT_EQ(cl.compiles() - compiles_before, 2) << source << ": " << renderer.stats().kernel_options;
    const SceneGeometry g = build_geometry(scene);
    const DeviceGeometry dg = upload_geometry(cl, g);
    const DeviceTracer tracer(cl, dg);
    const std::string render_options = renderer.stats().kernel_options;
    EXPECT_EQ(traversal_options(render_options), traversal_options(tracer.options()))
        << "render: " << render_options << "\nbench:  " << tracer.options();
    EXPECT_EQ(traversal_options(render_options).count("-cl-fast-relaxed-math"), 0u)
        << "the renderer relies on NaN/Inf checks that relaxed math may delete";
}

}  // namespace

TEST(ProgramOptions, BenchTracesWithTheRenderersTraversalOptions) {
    expect_same_traversal("builtin:strand?hairs=50&segments=8");
}

TEST(ProgramOptions, BenchTracesWithTheRenderersTraversalOptionsWithMeshes) {
    expect_same_traversal(std::string(HT_SOURCE_DIR) + "/scenes/strand_on_floor.gltf");
}
