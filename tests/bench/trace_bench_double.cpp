// Host traversal in double, one thread: ns per ray on the shared microbenchmark scene.
#define HT_BENCH_PRECISION "double"
#include "trace_bench_body.h"
