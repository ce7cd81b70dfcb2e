// --indirect afs shadow rays (kernels/stages/intersect_shadow_afs.cl): the transmittance is the
// product of AFS_TT^avg over the fibres crossed, each fibre counted once -- also where the ray
// passes a joint between two segments of one strand and intersects both capsules.
#include <gtest/gtest.h>

#include "bvh/bvh.h"
#include "bvh/device_geometry.h"
#include "fiber/afs_quadrature.h"
#include "kernels/fiber/afs.h"

#include <cmath>
#include <memory>
#include <vector>

namespace {

ht::ClContext& afs_cl() {
    static std::unique_ptr<ht::ClContext> ctx(new ht::ClContext());
    return *ctx;
}

// K straight strands along +x at y = 0.1 j, z = 0, radius 0.01, from x = -1 to 1 in 4 segments
// (joints at x = -0.5, 0, 0.5).
ht::Strands wall(int k) {
    ht::Strands s;
    s.first_point.push_back(0);
    for (int j = 0; j < k; ++j) {
        for (int i = 0; i <= 4; ++i) {
            s.points.push_back({-1.0f + 0.5f * i, 0.1f * j, 0.0f});
            s.radius.push_back(0.01f);
        }
        s.first_point.push_back((uint32_t)s.points.size());
        s.material.push_back(0);
    }
    return s;
}

template <class T>
cl::Buffer input(ht::ClContext& cl, const std::vector<T>& v) {
    return cl::Buffer(cl.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(T),
                      const_cast<T*>(v.data()));
}

std::vector<float> transmittance(const ht::SceneGeometry& geo, const float sigma_a[3], const std::vector<HtRay>& rays) {
    ht::ClContext& cl = afs_cl();
    ht::DeviceGeometry g = ht::upload_geometry(cl, geo);
    cl::Program prog = cl.build("stages/intersect_shadow_afs.cl", std::string(ht::base_kernel_options()) +
                                                         " -DHT_FEATURE_INDIRECT_AFS=1 -DHT_FEATURE_MESHES=0" +
                                                         ht::geometry_page_options(g.paging));
    cl::Kernel k(prog, "intersect_shadow_afs");
    const std::vector<uint32_t> strand_material(64, 0u);
    const std::vector<float> table = ht::afs_tt_table(1.55, sigma_a);
    cl::Buffer sm = input(cl, strand_material), tb = input(cl, table), rb = input(cl, rays);
    cl::Buffer out(cl.context(), CL_MEM_WRITE_ONLY, rays.size() * 4 * sizeof(float));
    cl_uint a = ht::set_paged_args(k, 0, g.nodes);
    a = ht::set_paged_args(k, a, g.segments);
    a = ht::set_paged_args(k, a, g.points);
    k.setArg(a++, sm);
    k.setArg(a++, tb);
    k.setArg(a++, rb);
    k.setArg(a++, out);
    k.setArg(a++, (cl_uint)rays.size());
    const size_t global = (rays.size() + 63) / 64 * 64;
    cl.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(global), cl::NDRange(64));
    std::vector<float> t(rays.size() * 4);
    cl.queue().enqueueReadBuffer(out, CL_TRUE, 0, t.size() * sizeof(float), t.data());
    return t;
}

HtRay ray_y(float x, float dx = 0.0f) {
    const float l = std::sqrt(1.0f + dx * dx);
    return HtRay{x, -1.0f, 0.0f, 0.0f, dx / l, 1.0f / l, 0.0f, 10.0f};
}

}  // namespace

TEST(AfsShadow, EveryFibreCountsOnceAlsoAtJoints) {
    const int K = 5;
    const ht::SceneGeometry geo = ht::build_geometry(wall(K));
    const float sigma_a[3] = {0.06f, 0.1f, 0.2f};
    std::vector<HtRay> rays = {
        ray_y(0.25f),          // mid-segment
        ray_y(0.0f),           // through the joint sphere, touching both capsules
        ray_y(-0.5f),          // another joint
        ray_y(1.5f),           // misses everything
    };
    std::vector<HtRay> short_ray = {ray_y(0.25f)};
    short_ray[0].tmax = 1.0f + 0.1f * 2 + 0.05f;  // ends between the 3rd and 4th fibre
    const std::vector<float> t = transmittance(geo, sigma_a, rays);
    const std::vector<float> ts = transmittance(geo, sigma_a, short_ray);
    for (int c = 0; c < 3; ++c) {
        // perpendicular crossings: theta = 0
        const double a = ht_afs_fast(1.55, sigma_a[c], 0.0, 1);
        for (int r = 0; r < 3; ++r)
            EXPECT_NEAR(t[4 * r + c], std::pow(a, K), 2e-4) << "ray " << r << " channel " << c;
        EXPECT_EQ(t[4 * 3 + c], 1.0f);
        EXPECT_NEAR(ts[c], std::pow(a, 3), 2e-4) << "short ray, channel " << c;
    }
}

TEST(AfsShadow, AShallowRayThroughAJointCrossesOneFibreOnce) {
    // In the plane of strand 0, 5.7 deg off its axis, crossing it at the joint x = 0: inside the
    // fibre for x in (-0.1, 0.1), so it intersects the capsules on both sides of the joint (the old
    // closest-hit loop could count the second one again).  tmax stops it before strand 1.
    const ht::SceneGeometry geo = ht::build_geometry(wall(2));
    const float sigma_a[3] = {0.06f, 0.1f, 0.2f};
    const double l = std::sqrt(1.0 + 0.01);
    const HtRay r{-0.5f, -0.05f, 0.0f, 0.0f, float(1 / l), float(0.1 / l), 0.0f, 0.9f};
    const std::vector<float> t = transmittance(geo, sigma_a, {r});
    const double theta = std::asin(1 / l);
    for (int c = 0; c < 3; ++c) {
        const double a = ht_afs_fast(1.55, sigma_a[c], theta, 1);  // ~0.05 at 84 deg: once vs twice is clear
        EXPECT_NEAR(t[c], a, 1e-4) << "channel " << c << " (twice would be " << a * a << ")";
    }
}

TEST(AfsShadow, OpaqueHairBlocksCompletely) {
    // AFS_TT < 1e-4 after a few crossings for very dark hair: the ray stops and reports 0
    const ht::SceneGeometry geo = ht::build_geometry(wall(5));
    const float sigma_a[3] = {8.0f, 10.0f, 12.0f};
    const std::vector<float> t = transmittance(geo, sigma_a, {ray_y(0.25f), ray_y(1.5f)});
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(t[c], 0.0f);
        EXPECT_EQ(t[4 + c], 1.0f);
        EXPECT_TRUE(std::isfinite(t[c]));
    }
}
