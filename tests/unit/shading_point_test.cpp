// Host (double) checks of the path-vertex interface that next-event estimation and the
// continuation share (kernels/integrator/shading_point.h): for a fibre and for a Lambertian
// surface, sample() and eval() agree on the pdf of the direction sample() chose, the sample's
// weight is eval's value over that pdf, and rays leave from outside the geometry on their side.
#include <gtest/gtest.h>

#include "fibre_point_util.h"

#include <cmath>
#include <cstring>

namespace {

using fibretest::fibre_point;
using fibretest::ray_towards;

void expect_sample_matches_eval(const HtShadingPoint& sp, double tol) {
    int sampled = 0;
    for (uint s = 0; s < 2000; ++s) {
        real3 wi, weight;
        real pdf = 0;
        if (!ht_point_sample(&sp, 7u, 3u, s, 0u, 1, &wi, &weight, &pdf)) continue;
        ++sampled;
        real3 value;
        real pdf_eval = 0;
        ht_point_eval(&sp, wi, &value, &pdf_eval);
        ASSERT_GT(pdf, 0);
        EXPECT_NEAR(pdf_eval / pdf, 1.0, tol) << "sample " << s;
        EXPECT_NEAR(weight.x, value.x / pdf, tol * std::max(1.0, weight.x)) << "sample " << s;
        EXPECT_NEAR(weight.z, value.z / pdf, tol * std::max(1.0, weight.z)) << "sample " << s;
    }
    EXPECT_GT(sampled, 1900);
}

TEST(ShadingPoint, FibreSampleAgreesWithEval) {
    for (const char* model : {"chiang", "zinke", "marschner"})
        for (double h : {-0.9, 0.0, 0.6}) expect_sample_matches_eval(fibre_point(h, model), 1e-6);
}

TEST(ShadingPoint, FibreRaysLeaveFromOutsideOnTheirSide) {
    const HtShadingPoint sp = fibre_point(0.3, "chiang");
    for (real3 w : {make_real3(1, 0, 0), make_real3(-0.6, 0.8, 0), make_real3(0, -0.2, -0.98),
                    make_real3(0, 1, 0) /* along the axis: any side will do */}) {
        const real3 o = ht_point_spawn(&sp, w);
        const real3 off = o - sp.axis_point;
        const real3 radial = off - sp.tangent * dot(off, sp.tangent);
        EXPECT_GT(length(radial), 0.5) << "inside the fibre";
        const real3 side = w - sp.tangent * dot(w, sp.tangent);
        if (dot(side, side) > 1e-12) {
            EXPECT_GT(dot(radial, side), 0) << "on the wrong side";
        }
    }
    EXPECT_NEAR(ht_point_shadow_tmax(&sp, 10.0), 10.0 - 0.505, 1e-12);
}

TEST(ShadingPoint, SurfaceSampleAgreesWithEvalAndLeavesOnItsSide) {
    HtTriangleShading ts;
    std::memset(&ts, 0, sizeof ts);
    ts.albedo[0] = 0.8f; ts.albedo[1] = 0.5f; ts.albedo[2] = 0.2f;
    ts.texture = HT_NO_TEXTURE;
    const HtRay ray = ray_towards(make_real3(0.2, 3, 0.1), make_real3(0, -1, 0));
    HtHit hit{};
    hit.t = 3;
    hit.u = 0.2f; hit.h = 0.3f;
    hit.tx = 0; hit.ty = -1; hit.tz = 0;  // the viewer is on the other side: face_forward flips it
    HtShadingPoint sp;
    ht_surface_point(ts, &ray, &hit, nullptr, 0, nullptr, &sp);
    EXPECT_GT(sp.ng.y, 0) << "the normal must face the viewer";
    expect_sample_matches_eval(sp, 1e-9);
    EXPECT_GT(ht_point_spawn(&sp, make_real3(0, 1, 0)).y, 0);
    EXPECT_LT(ht_point_spawn(&sp, make_real3(0, -1, 0)).y, 0);
}

}  // namespace
