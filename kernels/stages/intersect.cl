/* Program used by DeviceTracer: both intersection stages in one build. */
#include "intersect_closest.cl"
#include "intersect_shadow.cl"
