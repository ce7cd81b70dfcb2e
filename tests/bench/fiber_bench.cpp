// Host (double) cost of one eval and one sample per model: ns per call.
#include <benchmark/benchmark.h>

#include <vector>

#include "fiber/material.h"
#include "kernels/fiber/bcsdf.h"

using namespace ht;

namespace {
struct Inputs {
    std::vector<real3> wo, wi;
    std::vector<double> h, u;
};
const Inputs& inputs() {
    static Inputs in = [] {
        Inputs r;
        uint64_t s = 42;
        auto rnd = [&]() {
            s ^= s >> 12;
            s ^= s << 25;
            s ^= s >> 27;
            return (double)((s * 2685821657736338717ull) >> 11) * (1.0 / 9007199254740992.0);
        };
        for (int i = 0; i < 1024; ++i) {
            for (int k = 0; k < 2; ++k) {
                double z = 2 * rnd() - 1, p = 6.283185307179586 * rnd(), q = std::sqrt(1 - z * z);
                (k ? r.wi : r.wo).push_back(make_real3(z, q * std::cos(p), q * std::sin(p)));
            }
            r.h.push_back(2 * rnd() - 1);
            for (int k = 0; k < 4; ++k) r.u.push_back(rnd());
        }
        return r;
    }();
    return in;
}
HtMaterial material(int model) {
    const char* names[4] = {"kajiya", "marschner", "zinke", "chiang"};
    HairMaterialDesc d;
    d.model = names[model];
    d.has_sigma_a = true;
    d.sigma_a = {0.2f, 0.5f, 1.0f};
    return make_kernel_material(d);
}

void BM_Eval(benchmark::State& st) {
    HtMaterial m = material((int)st.range(0));
    const Inputs& in = inputs();
    size_t i = 0;
    for (auto _ : st) {
        real3 v;
        real pdf;
        ht_bcsdf_eval(&m, in.wo[i & 1023], in.wi[i & 1023], in.h[i & 1023], &v, &pdf);
        benchmark::DoNotOptimize(v);
        benchmark::DoNotOptimize(pdf);
        ++i;
    }
}
void BM_Sample(benchmark::State& st) {
    HtMaterial m = material((int)st.range(0));
    const Inputs& in = inputs();
    size_t i = 0;
    for (auto _ : st) {
        size_t k = i & 1023;
        real3 wi, w;
        real pdf;
        int ok = ht_bcsdf_sample(&m, in.wo[k], in.h[k], in.u[4 * k], in.u[4 * k + 1], in.u[4 * k + 2], in.u[4 * k + 3], &wi, &w, &pdf);
        benchmark::DoNotOptimize(ok);
        benchmark::DoNotOptimize(w);
        ++i;
    }
}
}  // namespace

// Argument: 0 kajiya, 1 marschner, 2 zinke, 3 chiang
BENCHMARK(BM_Eval)->DenseRange(0, 3);
BENCHMARK(BM_Sample)->DenseRange(0, 3);

// ---------------------------------------------------------------- OpenCL float kernel throughput
#include "cl/device.h"
#include "kernels/fiber/query.h"

namespace {
void BM_KernelEval(benchmark::State& st) {
    const int n = 1 << 18;
    const bool sample = st.range(1) != 0;
    try {
        static ClContext ctx;
        // the render programs' options (their floating-point mode: denormals flushed), plus any
        // extra ones to compare (HT_BENCH_OPTS)
        static cl::Program prog = ctx.build("fiber/fiber_query.cl", std::string(base_kernel_options()) + " " +
                                                                        (getenv("HT_BENCH_OPTS") ? getenv("HT_BENCH_OPTS") : ""));
        cl::Kernel k(prog, sample ? "fiber_sample" : "fiber_eval");
        const Inputs& in = inputs();
        std::vector<HtMaterial> mats(n, material((int)st.range(0)));
        std::vector<HtFiberQuery> qs(n);
        for (int i = 0; i < n; ++i) {
            int j = i & 1023;
            qs[i].wo[0] = (float)in.wo[j].x; qs[i].wo[1] = (float)in.wo[j].y; qs[i].wo[2] = (float)in.wo[j].z;
            qs[i].wi[0] = (float)in.wi[j].x; qs[i].wi[1] = (float)in.wi[j].y; qs[i].wi[2] = (float)in.wi[j].z;
            qs[i].h = (float)in.h[j];
            qs[i].u0 = (float)in.u[4 * j]; qs[i].u1 = (float)in.u[4 * j + 1]; qs[i].u2 = (float)in.u[4 * j + 2]; qs[i].u3 = (float)in.u[4 * j + 3];
        }
        cl::Buffer bm(ctx.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(HtMaterial), mats.data());
        cl::Buffer bq(ctx.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(HtFiberQuery), qs.data());
        cl::Buffer bo(ctx.context(), CL_MEM_WRITE_ONLY, n * sizeof(HtFiberResult));
        k.setArg(0, bm); k.setArg(1, bq); k.setArg(2, bo); k.setArg(3, (cl_uint)n);
        ctx.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(n), cl::NDRange(64));  // warm-up: PoCL
        ctx.queue().finish();                                                                // JIT per kernel
        for (auto _ : st) {
            ctx.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(n), cl::NDRange(64));
            ctx.queue().finish();
        }
        st.SetItemsProcessed(st.iterations() * n);
    } catch (const std::exception& e) {
        st.SkipWithError(e.what());
    }
}
}  // namespace
// Arguments: model (0 kajiya, 1 marschner, 2 zinke, 3 chiang), 0 eval / 1 sample.  items/s = queries/s.
BENCHMARK(BM_KernelEval)->ArgsProduct({{0, 1, 2, 3}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime();
