// Program builds: a build started in the background (ClContext::prefetch) must report its failure
// to the build() that collects it, and a program loaded from hairtrace's binary cache must render
// the same bits as the freshly compiled one even when PoCL's own cache is empty (the binary then
// carries every kernel's code: host/cl/device.cpp configure_pocl).  That the Renderer collects
// the prefetched builds is tested with the programs' options (program_options_test.cpp).
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

TEST(ProgramBuild, AFailedBackgroundBuildIsReportedByTheBuildThatCollectsIt) {
    ClContext cl;
    const std::string bad = std::string(base_kernel_options()) + " -DHT_TEST_BROKEN=1 -cl-no-such-option";
    cl.prefetch("stages/trace.cl", bad);
    EXPECT_THROW(cl.build("stages/trace.cl", bad), DeviceError);
    EXPECT_EQ(cl.compiles(), 1);
}

// A Renderer that fails after starting its program's compile in the background (here: the
// environment map, read after the recipe is known, does not exist) must not leave that compile
// running: a static context would wait for it only in its destructor, after PoCL's own teardown at
// exit, and the test process crashed there.
TEST(ProgramBuild, ARendererThatFailsLeavesNoBackgroundCompileBehind) {
    static ClContext cl;
    Scene scene = load_scene("builtin:strand?hairs=40&segments=8");
    scene.environment.map_path = "/nonexistent/hairtrace_env.exr";
    RenderSettings s;
    s.width = s.height = 32;
    s.spp = 1;
    s.max_depth = 2;
    const int before = cl.compiles();
    EXPECT_THROW(Renderer(cl, scene, s), SceneError);
    EXPECT_GT(cl.compiles(), before);  // the compiles did start: the case this test is about
    EXPECT_EQ(cl.pending_prefetches(), 0u);
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

// The binary carries the compiled work-group functions, so PoCL runs them as they are: a binary
// compiled under one work-group method must not be loaded by a process asking for another
// (host/cl/device.cpp pocl_code_settings).
TEST(ProgramBuild, ABinaryCompiledUnderAnotherPoclWorkGroupMethodIsNotLoaded) {
    TempDir d("ht_progmethod_");
    const std::string render = kBin + " render 'builtin:strand?hairs=40&segments=8' --width 16 --height 16 --spp 1 "
                                      "--max-depth 2 --verbose -o " + (d / "x.exr");
    const std::string env = "HAIRTRACE_CACHE_DIR=" + (d / "ht") + " POCL_CACHE_DIR=" + (d / "pocl") + " POCL_WORK_GROUP_METHOD=";
    ASSERT_EQ(run(env + "loopvec " + render + " 2>" + (d / "a.txt")), 0);
    ASSERT_EQ(run(env + "loops " + render + " 2>" + (d / "b.txt")), 0);
    ASSERT_EQ(run(env + "loops " + render + " 2>" + (d / "c.txt")), 0);
    EXPECT_EQ(slurp(d / "a.txt").find("(cached)"), std::string::npos) << slurp(d / "a.txt");
    EXPECT_EQ(slurp(d / "b.txt").find("(cached)"), std::string::npos) << slurp(d / "b.txt");
    EXPECT_NE(slurp(d / "c.txt").find("(cached)"), std::string::npos) << slurp(d / "c.txt");
}

}  // namespace
