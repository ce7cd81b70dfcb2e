// Host traversal in float, one thread: ns per ray on the shared microbenchmark scene.
// HT_HOST_REAL must come before anything that includes kernels/compat.h: this TU's `real` is float.
#define HT_HOST_REAL float
#define HT_BENCH_PRECISION "float"
#include "trace_bench_body.h"
