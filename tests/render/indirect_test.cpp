// How much hair-to-hair light a render includes: exact bounces, the paper's AFS approximation,
// none -- and the automatic depth.
#include <gtest/gtest.h>

#include "cl/device.h"
#include "render/depth_choice.h"
#include "render/renderer.h"
#include "scene/scene.h"

#include <cmath>

using namespace ht;

namespace {
ClContext& context() {
    static ClContext cl;
    return cl;
}

Film render(const Scene& scene, const RenderSettings& rs) {
    Renderer r(context(), scene, rs);
    Film f;
    r.render(f);
    return f;
}

double total(const Film& f) {
    double s = 0;
    for (size_t i = 0; i < size_t(f.width) * f.height; ++i)
        for (int c = 0; c < 3; ++c) {
            EXPECT_TRUE(std::isfinite(f.mean(i, c)));
            s += f.mean(i, c);
        }
    return s;
}

Scene strand() {
    Scene s = load_scene("builtin:strand?hairs=200&segments=16");
    ensure_camera_and_light(s);
    return s;
}

RenderSettings small() {
    RenderSettings rs;
    rs.width = rs.height = 40;
    rs.spp = 4;
    return rs;
}
}  // namespace

TEST(Indirect, DepthOneIsDirectLightAndOnlyAddsLightWithDepth) {
    Scene s = strand();
    RenderSettings rs = small();
    rs.max_depth = 1;
    Film direct = render(s, rs);
    Film again = render(s, rs);
    EXPECT_EQ(direct.rgba, again.rgba);
    double prev = total(direct);
    for (int d : {2, 3, 5}) {
        rs.max_depth = d;
        double t = total(render(s, rs));
        EXPECT_GT(t, prev) << "depth " << d;  // every added bounce adds (non-negative) light
        prev = t;
    }
}

TEST(Indirect, AfsTailBrightensDirectLightButStaysBelowTheExactPathTracer) {
    Scene s = strand();
    for (auto& m : s.materials) m.model = "zinke";
    RenderSettings rs = small();
    rs.spp = 8;
    rs.max_depth = 1;
    double none = total(render(s, rs));
    rs.indirect = RenderSettings::Indirect::Afs;
    double afs = total(render(s, rs));
    rs.indirect = RenderSettings::Indirect::Exact;
    rs.max_depth = 8;
    double exact = total(render(s, rs));
    // Translucent shadows only remove occlusion; the AFS tail then approximates what exact
    // multiple scattering adds.  Measured here: none < afs < exact (afs recovers part of it).
    EXPECT_GT(afs, none * 1.01);
    EXPECT_LT(afs, exact * 1.5);
    RecordProperty("none", std::to_string(none));
    RecordProperty("afs", std::to_string(afs));
    RecordProperty("exact", std::to_string(exact));
}

TEST(Indirect, AutomaticDepthFollowsAbsorption) {
    Scene s = strand();
    s.materials[0].model = "zinke";
    s.materials[0].set_sigma_a({0.1f, 0.1f, 0.1f});
    DepthChoice blond = choose_max_depth(s);
    EXPECT_EQ(blond.depth, 5) << blond.why;  // 0.7067^5 = 0.176 < 0.2 (the paper's ~5 bounces)
    s.materials[0].sigma_a = {2.0f, 2.0f, 2.0f};
    DepthChoice dark = choose_max_depth(s);
    EXPECT_LE(dark.depth, 2) << dark.why;  // the paper: 1-2 for dark hair
}

TEST(Indirect, ClampBoundsEveryIndirectSampleAndLeavesDirectLightAlone) {
    // Point light only: the light a path adds after its first scattering is NEE at bounces 1..D-1,
    // each capped at C in its largest channel, so per pixel 0 <= clamped(D) - direct <= (D-1) C
    // (the same seed draws the same direct-light samples at every depth).  A cap no sample
    // reaches changes no bit.
    Scene s = strand();
    RenderSettings rs = small();
    rs.spp = 8;
    rs.max_depth = 1;
    Film direct = render(s, rs);
    rs.max_depth = 3;
    Film exact = render(s, rs);
    rs.clamp_indirect = 1e30f;
    EXPECT_EQ(render(s, rs).rgba, exact.rgba);
    const float cap = 2e-3f;
    rs.clamp_indirect = cap;
    Film clamped = render(s, rs);
    EXPECT_LT(total(clamped), total(exact));
    EXPECT_GT(total(clamped), total(direct));
    for (size_t i = 0; i < size_t(rs.width) * rs.height; ++i)
        for (int c = 0; c < 3; ++c) {
            const float d = clamped.mean(i, c) - direct.mean(i, c);
            EXPECT_GE(d, -1e-6f * direct.mean(i, c) - 1e-9f) << i;
            EXPECT_LE(d, 2.0f * cap * (1.0f + 1e-5f)) << i;
        }
}

TEST(Indirect, RegularisationLeavesDirectLightAndKeepsTheEnergyOfIndirectLight) {
    // Widening the lobes after the first scattering changes nothing a camera ray sees directly
    // (depth 1: same bits) and, the lobes being normalised, moves the image's total energy only
    // a little: within 10 % at depth 3 (measured +3 % / -4 % at 10 / 20 degrees on the full strand).
    Scene s = strand();
    RenderSettings rs = small();
    rs.spp = 16;
    rs.max_depth = 1;
    Film direct = render(s, rs);
    rs.regularize_deg = 20.0f;
    EXPECT_EQ(render(s, rs).rgba, direct.rgba);
    // 64 samples: at 16 one rare two-lobe path (a sparkle) can move the unregularised total by
    // 25 % (seen with the Sobol' sampler), which is the noise this test is not about
    rs.max_depth = 3;
    rs.spp = 64;
    Film regularised = render(s, rs);
    rs.regularize_deg = 0.0f;
    Film exact = render(s, rs);
    EXPECT_NE(regularised.rgba, exact.rgba) << "the option must reach the kernels";
    EXPECT_NEAR(total(regularised), total(exact), 0.10 * total(exact));
}
