// The traversal microbenchmarks, compiled once per precision: the including file defines
// HT_HOST_REAL (or not, for double) and HT_BENCH_PRECISION ("float" / "double") first.
#include <benchmark/benchmark.h>

#include <string>

#include "kernels/geometry/bvh_traverse.h"

#include "trace_bench_scene.h"

namespace {

void closest(benchmark::State& state, bool incoherent) {
    const auto& s = ht_bench::trace_scene();
    const auto& rays = incoherent ? s.incoherent : s.primary;
    size_t i = 0, hits = 0;
    for (auto _ : state) {
        HtHit h;
        ht_trace_closest(s.geo.nodes.data(), s.geo.segments.data(), s.geo.points.data(), rays[i], &h);
        hits += h.segment != HT_NO_HIT;
        benchmark::DoNotOptimize(h);
        i = (i + 1) % rays.size();
    }
    state.counters["hit_rate"] = benchmark::Counter((double)hits / state.iterations());
    state.SetItemsProcessed(state.iterations());
}

void any(benchmark::State& state) {
    const auto& s = ht_bench::trace_scene();
    size_t i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(ht_trace_any(s.geo.nodes.data(), s.geo.segments.data(),
                                              s.geo.points.data(), s.incoherent[i]));
        i = (i + 1) % s.incoherent.size();
    }
    state.SetItemsProcessed(state.iterations());
}

}  // namespace

BENCHMARK_CAPTURE(closest, primary, false)->Name(std::string(HT_BENCH_PRECISION) + "_primary");
BENCHMARK_CAPTURE(closest, incoherent, true)->Name(std::string(HT_BENCH_PRECISION) + "_incoherent");
BENCHMARK(any)->Name(std::string("any_") + HT_BENCH_PRECISION + "_incoherent");
