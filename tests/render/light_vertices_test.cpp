// --light-vertices N (kernels/integrator/light_vertices.h, kernels/stages/shade.cl): light-vertex
// next-event estimation.  Each camera sample traces N light rays; every fibre vertex before the
// last connects to the first fibre hit of one of them, and the connection shares the paths
// x -> y -> light with the continuation from x (followed by y's own estimate) by the balance
// heuristic, so the image converges to the one without them; the densities the weights are made of
// are checked against the rays that make the vertices in tests/unit/light_vertices_test.cpp.  The
// library (and the command line) leaves it off: it did not pay (docs/PERFORMANCE.md section 8).
#include "render/prepared_scene.h"
#include "render/renderer.h"
#include "scene/scene.h"

#include <gtest/gtest.h>

#include "cli_test_util.h"
#include "render_test_util.h"

#include <string>

using namespace ht;
using rendertest::image_mean;
using rendertest::render;
using rendertest::thick_strand;

namespace {

RenderSettings settings(uint32_t light_vertices, int spp, uint32_t seed, int depth = 3) {
    RenderSettings rs = rendertest::small_settings(spp, seed, depth);
    rs.light_vertices = light_vertices;
    rs.sampler = RenderSettings::Sampler::Independent;
    return rs;
}

TEST(LightVertices, TheLibrarysDefaultIsOff) { EXPECT_EQ(RenderSettings{}.light_vertices, 0u); }

TEST(LightVertices, ConvergesToTheMeanWithoutThem) {
    // The thick strand (a point light) at depth 3: every vertex of bounces 0 and 1 connects.  The
    // reference is 1,024 spp without light vertices; the MIS sum at 256 spp, seed 3, must agree
    // within 2 % (the tolerance of the other unbiased estimators' tests, light_threshold_test.cpp;
    // the same seed without light vertices is 0.20 % off).  Measured: +0.17 % (64 light rays per
    // sample) and +0.30 % (1,024).
    const Scene scene = thick_strand();
    const double reference = image_mean(render(scene, settings(0, 1024, 99)));
    ASSERT_GT(reference, 0.0);
    for (uint32_t n : {64u, 1024u}) {
        RenderStats on, off;
        const double mean = image_mean(render(scene, settings(n, 256, 3), &on));
        EXPECT_NEAR(mean / reference, 1.0, 0.02) << n << " light rays: " << mean << " against " << reference;
        render(scene, settings(0, 256, 3), &off);
        EXPECT_EQ(on.light_rays, uint64_t(n) * 256u) << "N light rays per camera sample";
        EXPECT_GT(on.shadow_rays, off.shadow_rays) << "the connections are shadow rays too";
        EXPECT_EQ(on.extension_rays, off.extension_rays) << "the paths themselves are not changed";
        EXPECT_EQ(off.light_rays, 0u);
    }
}

TEST(LightVertices, TheImageIsAPureFunctionOfSeedPixelAndSample) {
    // Light rays belong to camera samples (their own Sobol' indices), so passes of any size and
    // sample ranges give the same bits: 11 samples one to a pass, or 5 + 6 at four to a pass.
    const Scene scene = rendertest::sparse_strand();
    RenderSettings rs = rendertest::small_settings(1, 3, 3);
    rs.light_vertices = 32;
    rs.first_hit_splits = 2;
    Film a, b;
    a.width = b.width = rs.width, a.height = b.height = rs.height;
    a.rgba.assign(4 * size_t(rs.width) * rs.height, 0.0f);
    b.rgba = a.rgba;
    rs.samples_per_pass = 1;
    {
        Renderer r(rendertest::context(), scene, rs);
        r.upload_film(a);
        for (uint32_t i = 0; i < 11; ++i) r.render_sample(i);
        r.download_film(a);
    }
    rs.samples_per_pass = 4;
    {
        Renderer r(rendertest::context(), scene, rs);
        r.upload_film(b);
        r.render_samples(0, 5);
        r.render_samples(5, 6);
        r.download_film(b);
    }
    EXPECT_EQ(a.rgba, b.rgba);
    rs.light_vertices = 0;
    Film c = a;
    std::fill(c.rgba.begin(), c.rgba.end(), 0.0f);
    {
        Renderer r(rendertest::context(), scene, rs);
        r.upload_film(c);
        r.render_samples(0, 11);
        r.download_film(c);
    }
    EXPECT_NE(a.rgba, c.rgba) << "the connections changed the image";
}

TEST(LightVertices, OffAtDepthOne) {
    // no vertex has a connection to make: the settings say so and the image is the one without
    const Scene scene = thick_strand();
    RenderSettings with = settings(64, 2, 1, 1);
    EXPECT_EQ(prepare_scene(scene, with).settings.light_vertices, 0u);
    EXPECT_EQ(render(scene, with).rgba, render(scene, settings(0, 2, 1, 1)).rgba);
}

TEST(LightVertices, NeedsALightThatStartsRays) {
    Scene scene = thick_strand();
    for (Light& l : scene.lights) {
        l.type = LightType::Sphere;
        l.radius = 1.0f;
    }
    EXPECT_THROW(render(scene, settings(64, 1, 1)), std::invalid_argument);
}

}  // namespace

#ifdef HT_BINARY
TEST(LightVerticesCli, OffByDefaultTheRangeAndTheCombinationsAreChecked) {
    clitest::TempDir d("ht_light_vertices_");
    clitest::expect_option_default(d, clitest::kSmallStrandRender + " --spp 2", "--light-vertices off",
                                   "--light-vertices 64",
                                   {"--light-vertices 0", "--light-vertices 4097", "--light-vertices -1",
                                    "--light-vertices many"});
    // what it cannot be combined with: a usage error (exit 2) that names it
    for (const std::string& bad : {std::string(" --indirect afs"), std::string(" --aovs albedo")}) {
        const std::string err = d / "err.txt";
        EXPECT_EQ(clitest::run(clitest::kSmallStrandRender + " --spp 1 --light-vertices 64" + bad + " -o " +
                               (d / "x.exr") + " 2>" + err),
                  2)
            << bad;
        EXPECT_NE(clitest::slurp(err).find("--light-vertices"), std::string::npos) << clitest::slurp(err);
    }
}

TEST(LightVerticesCli, ChunksThreadsDevicesPartsAndCheckpointsGiveTheSameBits) {
    // the light rays are a pure function of (seed, sample, ray), like every other draw
    clitest::TempDir d("ht_light_vertices_bits_");
    using clitest::image;
    using clitest::run;
    const std::string lv = clitest::kSmallStrandRender + " --light-vertices 64 --spp 8";
    clitest::expect_same_bits_in_chunks_threads_devices_and_parts(d, lv);
    // a checkpoint resumes with the same light vertices only
    ASSERT_EQ(run(lv + " --chunk 16 -o " + (d / "whole.exr")), 0);
    ASSERT_EQ(run(clitest::kSmallStrandRender + " --light-vertices 64 --spp 2 --chunk 16 --checkpoint " +
                  (d / "c.ckpt") + " -o " + (d / "a.exr")),
              0);
    const std::string resume = " --spp 8 --chunk 16 --resume " + (d / "c.ckpt") + " -o " + (d / "b.exr") + " 2>/dev/null";
    EXPECT_EQ(run(clitest::kSmallStrandRender + " --light-vertices 32" + resume), 2);
    EXPECT_EQ(run(clitest::kSmallStrandRender + resume), 2);
    ASSERT_EQ(run(lv + " --chunk 16 --resume " + (d / "c.ckpt") + " -o " + (d / "resumed.exr")), 0);
    EXPECT_EQ(image(d / "whole.exr"), image(d / "resumed.exr"));
}
#endif
