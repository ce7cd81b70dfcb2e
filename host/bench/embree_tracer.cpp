#include "bench/embree_tracer.h"

#include "cl/device.h"
#include "io/rays_file.h"
#include "core/errors.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

#ifdef HT_HAVE_EMBREE
#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <xmmintrin.h>
#endif

namespace ht {

#ifdef HT_HAVE_EMBREE

bool embree_available() { return true; }

struct EmbreeTracer::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    double build_ms = 0;
};

EmbreeTracer::EmbreeTracer(const Strands& strands) : impl_(new Impl) {
    impl_->device = rtcNewDevice("threads=2");
    if (!impl_->device) throw DeviceError("Embree: rtcNewDevice failed");
    impl_->scene = rtcNewScene(impl_->device);
    RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
    const size_t np = strands.point_count(), ns = strands.segment_count();
    float* v = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 16, std::max<size_t>(np, 1)));
    for (size_t i = 0; i < np; ++i) {
        v[4 * i + 0] = strands.points[i][0];
        v[4 * i + 1] = strands.points[i][1];
        v[4 * i + 2] = strands.points[i][2];
        v[4 * i + 3] = strands.radius[i];
    }
    unsigned* idx = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, 4, std::max<size_t>(ns, 1)));
    size_t k = 0;  // segments back to back by strand: primID = global segment index
    for (size_t s = 0; s < strands.strand_count(); ++s)
        for (uint32_t p = strands.first_point[s]; p + 1 < strands.first_point[s + 1]; ++p) idx[k++] = p;
    rtcCommitGeometry(g);
    rtcAttachGeometry(impl_->scene, g);
    rtcReleaseGeometry(g);
    const auto t0 = std::chrono::steady_clock::now();
    rtcCommitScene(impl_->scene);
    impl_->build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

EmbreeTracer::~EmbreeTracer() {
    if (impl_->scene) rtcReleaseScene(impl_->scene);
    if (impl_->device) rtcReleaseDevice(impl_->device);
}

double EmbreeTracer::build_ms() const { return impl_->build_ms; }

namespace {
// One pass over every ray on 2 threads (4096-ray chunks), as the anchor times it: flag[i] = hit or
// occluded; with `out`, also Embree's full closest-hit record (the anchor's .rays layout).
void embree_pass(RTCScene scene, const std::vector<HtRay>& rays, bool shadow, unsigned char* flag, EmbreeHit* out) {
    const size_t n = rays.size(), chunk = 4096;
    std::atomic<size_t> next{0};
    auto worker = [&]() {
        // as the anchor: flush denormals, Embree's recommendation
        _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
        _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        for (size_t b; (b = next.fetch_add(chunk)) < n;)
            for (size_t i = b; i < std::min(n, b + chunk); ++i) {
                const HtRay& r = rays[i];
                RTCRayHit rh;
                rh.ray.org_x = r.ox; rh.ray.org_y = r.oy; rh.ray.org_z = r.oz; rh.ray.tnear = r.tmin;
                rh.ray.dir_x = r.dx; rh.ray.dir_y = r.dy; rh.ray.dir_z = r.dz;
                rh.ray.tfar = r.tmax >= 1e29f ? 3e38f : r.tmax;
                rh.ray.time = 0; rh.ray.mask = ~0u; rh.ray.id = 0; rh.ray.flags = 0;
                if (shadow) {
                    rtcOccluded1(scene, &ctx, &rh.ray);
                    flag[i] = rh.ray.tfar < 0;  // Embree marks occlusion with tfar = -inf
                    continue;
                }
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(scene, &ctx, &rh);
                flag[i] = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
                if (out)
                    out[i] = flag[i] ? EmbreeHit{rh.ray.tfar, rh.hit.primID, rh.hit.u, rh.hit.v,
                                                 {rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z}}
                                     : kEmbreeMiss;
            }
    };
    std::thread t1(worker), t2(worker);
    t1.join();
    t2.join();
}
}  // namespace

double EmbreeTracer::pass_ms(const std::vector<HtRay>& rays, bool shadow) {
    std::vector<unsigned char> result(rays.size());
    const auto t0 = std::chrono::steady_clock::now();
    embree_pass(impl_->scene, rays, shadow, result.data(), nullptr);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void EmbreeTracer::answer(const std::vector<HtRay>& rays, bool shadow, std::vector<EmbreeHit>& hits,
                          std::vector<uint32_t>& occluded) {
    std::vector<unsigned char> flag(rays.size());
    hits.assign(shadow ? 0 : rays.size(), EmbreeHit{});
    embree_pass(impl_->scene, rays, shadow, flag.data(), shadow ? nullptr : hits.data());
    occluded.assign(flag.begin(), flag.end());
    if (!shadow) occluded.clear();
}

#else

bool embree_available() { return false; }
struct EmbreeTracer::Impl {};
EmbreeTracer::EmbreeTracer(const Strands&) {
    throw UsageError("bench --embree: this build has no Embree (apt-get install libembree-dev, then reconfigure)");
}
EmbreeTracer::~EmbreeTracer() = default;
double EmbreeTracer::build_ms() const { return 0; }
double EmbreeTracer::pass_ms(const std::vector<HtRay>&, bool) { return 0; }
void EmbreeTracer::answer(const std::vector<HtRay>&, bool, std::vector<EmbreeHit>&, std::vector<uint32_t>&) {}

#endif

}  // namespace ht
