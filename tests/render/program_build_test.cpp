// Program builds: the render program is compiled while the host builds the BVH (ClContext::prefetch,
// prefetch_render_program) and the Renderer must collect that build rather than compile a second
// one; a background failure must reach the caller; and a program loaded from hairtrace's binary
// cache must render the same bits as the freshly compiled one even when PoCL's own cache is empty
// (the binary then carries every kernel's code: host/cl/device.cpp configure_pocl).
#include <gtest/gtest.h>

#include "cl/device.h"
#include "render/renderer.h"
#include "scene/scene.h"

#include "cli_test_util.h"

#include <string>

using namespace ht;
using namespace clitest;

namespace {

const std::string kBin = HT_BINARY;

TEST(ProgramBuild, RendererCollectsTheBuildStartedBeforeTheBvh) {
    for (const char* source : {"builtin:strand?hairs=40&segments=8", "builtin:ball?hairs=40&segments=8"}) {
        ClContext cl;
        Scene scene = load_scene(source);
        ensure_camera_and_light(scene);
        RenderSettings rs;
        rs.width = rs.height = 8;
        rs.spp = 1;
        Renderer renderer(cl, scene, rs);
        // two programs (trace and shade), each compiled once
        EXPECT_EQ(cl.compiles(), 2) << source << ": the prefetched options differ from the Renderer's: "
                                    << renderer.stats().kernel_options;
    }
}

TEST(ProgramBuild, AFailedBackgroundBuildIsReportedByTheBuildThatCollectsIt) {
    ClContext cl;
    const std::string bad = std::string(base_kernel_options()) + " -DHT_TEST_BROKEN=1 -cl-no-such-option";
    cl.prefetch("stages/trace.cl", bad);
    EXPECT_THROW(cl.build("stages/trace.cl", bad), DeviceError);
    EXPECT_EQ(cl.compiles(), 1);
}

TEST(ProgramBuild, ImageFromTheBinaryCacheWithAnEmptyPoclCacheHasTheSameBits) {
    TempDir d("ht_progcache_");
    const std::string render = kBin + " render 'builtin:strand?hairs=60&segments=8' --width 24 --height 24 --spp 2 "
                                      "--max-depth 3 --verbose";
    const std::string cache = "HAIRTRACE_CACHE_DIR=" + (d / "ht");
    ASSERT_EQ(run(cache + " POCL_CACHE_DIR=" + (d / "pocl1") + " " + render + " -o " + (d / "a.exr") + " 2>" +
                  (d / "a.txt")),
              0);
    ASSERT_EQ(run(cache + " POCL_CACHE_DIR=" + (d / "pocl2") + " " + render + " -o " + (d / "b.exr") + " 2>" +
                  (d / "b.txt")),
              0);
    EXPECT_EQ(slurp(d / "a.txt").find("(cached)"), std::string::npos) << slurp(d / "a.txt");
    EXPECT_NE(slurp(d / "b.txt").find("(cached)"), std::string::npos) << slurp(d / "b.txt");
    EXPECT_EQ(image(d / "a.exr"), image(d / "b.exr"));
}

}  // namespace
