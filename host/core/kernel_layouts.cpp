// The host compiler's side of the layout contract (kernels/layouts.h): a struct whose C++ layout
// differs from the declared one fails the build here.  The device compiler's side is checked by
// tests/kernel/layout_test.cpp with the same list.
#include "kernels/geometry/pages.h"
#include "kernels/layouts.h"

#include <cstddef>

namespace ht {

#define HT_CHECK_SIZE(T, bytes) \
    static_assert(sizeof(T) == (bytes), #T ": size differs from kernels/layouts.h"); \
    static_assert(sizeof(T) % 8 == 0, #T ": shared structs are whole 8-byte words");
#define HT_CHECK_FIELD(T, field, offset) \
    static_assert(offsetof(T, field) == (offset), #T "." #field ": offset differs from kernels/layouts.h");
HT_SHARED_LAYOUTS(HT_CHECK_SIZE, HT_CHECK_FIELD)
#undef HT_CHECK_SIZE
#undef HT_CHECK_FIELD

// Paged geometry finds record i by shift and mask (kernels/geometry/pages.h).
static_assert(sizeof(HtBvhNode) == 1u << HT_NODE_BYTES_LOG2, "kernels/geometry/pages.h: HtBvhNode size");
static_assert(sizeof(HtSegment) == 1u << HT_SEGMENT_BYTES_LOG2, "kernels/geometry/pages.h: HtSegment size");
static_assert(sizeof(HtPoint) == 1u << HT_POINT_BYTES_LOG2, "kernels/geometry/pages.h: HtPoint size");
static_assert(sizeof(HtTriangleShading) == 1u << HT_TRIANGLE_BYTES_LOG2,
              "kernels/geometry/pages.h: HtTriangleShading size");

}  // namespace ht
