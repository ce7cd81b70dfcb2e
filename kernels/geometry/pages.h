/* Scene geometry larger than one device allocation: every geometry array the kernels index (BVH
 * nodes, leaf segment records, points, triangle shading) may be split into HT_GEOMETRY_PAGES
 * buffers ("pages") of 2^HT_GEOMETRY_PAGE_LOG2 bytes each, passed as separate kernel arguments.
 *
 * OpenCL C 1.2 has no program-scope pointers and no pointers inside kernel-argument structs, so
 * the pages cannot be gathered into a table: the parameter lists and the accessors below expand
 * to K separate pointers and a select on the page number.  Element i of an array of 2^e-byte
 * records lives in page i >> (LOG2 - e) at offset i & (2^(LOG2 - e) - 1); both are compile-time
 * shifts and masks.
 *
 * HT_GEOMETRY_PAGES = 1 (the default, and what the host chooses whenever every array fits in
 * one allocation) expands to exactly the single-pointer code: `segs[i]`, `nodes + i`.  The host
 * (host/render/memory_plan.h plan_geometry_pages) picks K <= 8 and the page size, and passes
 * both through the kernel build options (host/render/features.cpp).
 *
 * Code indexing geometry uses the parameter names nodes, segs, points, tri_shading through
 * HT_*_PARAM / HT_*_ARG and reads elements only through HT_NODE_PTR, HT_SEG, HT_POINT and
 * HT_TRI_SHADING. */
#ifndef HT_GEOMETRY_PAGES_H
#define HT_GEOMETRY_PAGES_H

#include "../types.h"

/* log2 of each paged record's size; host/core/kernel_layouts.cpp asserts them against sizeof. */
#define HT_NODE_BYTES_LOG2 8      /* HtBvhNode */
#define HT_SEGMENT_BYTES_LOG2 3   /* HtSegment */
#define HT_POINT_BYTES_LOG2 4     /* HtPoint */
#define HT_TRIANGLE_BYTES_LOG2 7  /* HtTriangleShading */
#define HT_MAX_GEOMETRY_PAGES 8

#ifndef HT_GEOMETRY_PAGES
#define HT_GEOMETRY_PAGES 1
#endif

#if HT_GEOMETRY_PAGES == 1

#define HT_NODES_PARAM HT_CONST_GLOBAL HtBvhNode* nodes
#define HT_SEGS_PARAM HT_CONST_GLOBAL HtSegment* segs
#define HT_POINTS_PARAM HT_CONST_GLOBAL HtPoint* points
#define HT_TRIS_PARAM HT_CONST_GLOBAL HtTriangleShading* tri_shading
#define HT_NODES_ARG nodes
#define HT_SEGS_ARG segs
#define HT_POINTS_ARG points
#define HT_TRIS_ARG tri_shading
#define HT_NODE_PTR(i) (nodes + (i))
#define HT_SEG(i) segs[i]
#define HT_POINT(i) points[i]
#define HT_TRI_SHADING(i) tri_shading[i]

#else

#if HT_GEOMETRY_PAGES < 1 || HT_GEOMETRY_PAGES > HT_MAX_GEOMETRY_PAGES
#error "HT_GEOMETRY_PAGES must be 1..8"
#endif
#ifndef HT_GEOMETRY_PAGE_LOG2
#error "HT_GEOMETRY_PAGES > 1 needs HT_GEOMETRY_PAGE_LOG2 (log2 of the page size in bytes)"
#endif
#if HT_GEOMETRY_PAGE_LOG2 < HT_NODE_BYTES_LOG2 || HT_GEOMETRY_PAGE_LOG2 > 35
#error "HT_GEOMETRY_PAGE_LOG2 must hold at least one node record (the largest) and index pages with uint"
#endif

#define HT_PCAT_(a, b) a##b
#define HT_PCAT(a, b) HT_PCAT_(a, b)

/* T n0, T n1, ..., T n{K-1} (T empty: the names alone) */
#define HT_PLIST_1(T, n) T n##0
#define HT_PLIST_2(T, n) HT_PLIST_1(T, n), T n##1
#define HT_PLIST_3(T, n) HT_PLIST_2(T, n), T n##2
#define HT_PLIST_4(T, n) HT_PLIST_3(T, n), T n##3
#define HT_PLIST_5(T, n) HT_PLIST_4(T, n), T n##4
#define HT_PLIST_6(T, n) HT_PLIST_5(T, n), T n##5
#define HT_PLIST_7(T, n) HT_PLIST_6(T, n), T n##6
#define HT_PLIST_8(T, n) HT_PLIST_7(T, n), T n##7
#define HT_PLIST(T, n) HT_PCAT(HT_PLIST_, HT_GEOMETRY_PAGES)(T, n)

/* the pointer to page p of array n */
#define HT_PSEL_1(n, p) n##0
#define HT_PSEL_2(n, p) ((p) == 1u ? n##1 : HT_PSEL_1(n, p))
#define HT_PSEL_3(n, p) ((p) == 2u ? n##2 : HT_PSEL_2(n, p))
#define HT_PSEL_4(n, p) ((p) == 3u ? n##3 : HT_PSEL_3(n, p))
#define HT_PSEL_5(n, p) ((p) == 4u ? n##4 : HT_PSEL_4(n, p))
#define HT_PSEL_6(n, p) ((p) == 5u ? n##5 : HT_PSEL_5(n, p))
#define HT_PSEL_7(n, p) ((p) == 6u ? n##6 : HT_PSEL_6(n, p))
#define HT_PSEL_8(n, p) ((p) == 7u ? n##7 : HT_PSEL_7(n, p))
#define HT_PSEL(n, p) HT_PCAT(HT_PSEL_, HT_GEOMETRY_PAGES)(n, p)

#define HT_PAGE_SHIFT(e) (HT_GEOMETRY_PAGE_LOG2 - (e))
#define HT_PAGE_MASK(e) ((1u << HT_PAGE_SHIFT(e)) - 1u)
#define HT_PAGED_PTR(n, e, i) (HT_PSEL(n, (uint)(i) >> HT_PAGE_SHIFT(e)) + ((uint)(i) & HT_PAGE_MASK(e)))

#define HT_NODES_PARAM HT_PLIST(HT_CONST_GLOBAL HtBvhNode*, nodes)
#define HT_SEGS_PARAM HT_PLIST(HT_CONST_GLOBAL HtSegment*, segs)
#define HT_POINTS_PARAM HT_PLIST(HT_CONST_GLOBAL HtPoint*, points)
#define HT_TRIS_PARAM HT_PLIST(HT_CONST_GLOBAL HtTriangleShading*, tri_shading)
#define HT_NODES_ARG HT_PLIST(, nodes)
#define HT_SEGS_ARG HT_PLIST(, segs)
#define HT_POINTS_ARG HT_PLIST(, points)
#define HT_TRIS_ARG HT_PLIST(, tri_shading)
#define HT_NODE_PTR(i) HT_PAGED_PTR(nodes, HT_NODE_BYTES_LOG2, i)
#define HT_SEG(i) (*HT_PAGED_PTR(segs, HT_SEGMENT_BYTES_LOG2, i))
#define HT_POINT(i) (*HT_PAGED_PTR(points, HT_POINT_BYTES_LOG2, i))
#define HT_TRI_SHADING(i) (*HT_PAGED_PTR(tri_shading, HT_TRIANGLE_BYTES_LOG2, i))

#endif

/* The three arrays traversal reads. */
#define HT_GEOMETRY_PARAMS HT_NODES_PARAM, HT_SEGS_PARAM, HT_POINTS_PARAM
#define HT_GEOMETRY_ARGS HT_NODES_ARG, HT_SEGS_ARG, HT_POINTS_ARG

#endif /* HT_GEOMETRY_PAGES_H */
