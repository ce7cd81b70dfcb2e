// Binned-SAH BVH over capsule segments, built with a few std::threads and flattened depth-first
// into HtBvhNode ("SoA in node": each node holds both children's boxes).
#include "bvh/bvh.h"
#include "core/parallel.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <stdexcept>
#include <thread>
#include <type_traits>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "kernels/geometry/bvh_traverse.h"

// The stack holds at most HT_BVH_WIDTH - 1 entries per level of the path to the current node, so
// the depth cap keeps it safe: Flattener::visit opens at least kCollapseLevels binary levels per
// 8-wide node, so an inner 8-wide node sits at binary depth >= kCollapseLevels x its own.
constexpr int kCollapseLevels = 3;
// References per child whose frame box bounds an oriented node's cost from below before the full
// boxes are computed (Flattener::visit).
constexpr uint32_t kBoundSample = 32;
static_assert(1 << kCollapseLevels == HT_BVH_WIDTH, "three full binary levels fill one node");
// + 1: the root's entry, below a start node's subtree (kernels/geometry/bvh_traverse.h ht_traverse_from)
static_assert((HT_BVH_WIDTH - 1) * (ht::kMaxBvhDepth / kCollapseLevels + 1) + 1 < HT_STACK_SIZE,
              "BVH depth cap must fit the kernel stack");

namespace ht {
namespace {

// The build's threads (BvhOptions::threads, 0 = one per hardware thread).
unsigned build_threads(const BvhOptions& opt) {
    return opt.threads ? opt.threads : std::max(1u, std::thread::hardware_concurrency());
}

// The threads a pass over n elements uses: at most `threads`, and none beside the calling thread
// below 16,384 elements a thread, so that small scenes start no threads for it (for_ranges,
// Flattener::moments_of; a threshold chosen, not tuned).
unsigned pass_threads(size_t n, unsigned threads) {
    constexpr size_t kMinPerThread = 16384;
    return unsigned(std::max<size_t>(1, std::min<size_t>(threads, n / kMinPerThread)));
}

// The build's arrays (points, segment records, references, intermediate nodes: ~30 MB for 250k
// segments) are written once into fresh memory, and on this project's KVM guests a first touch of
// a 4 KiB page costs ~10 us (8 MiB: 20 ms), so page faults were about half of the build
// (host/bvh/NOTES.md "Build time: page faults").  So every array of the build, and the
// geometry's own, is a BulkVector (core/bulk_vector.h): 2 MiB-aligned transparent huge pages,
// one fault per 2 MiB, and no zero fill of what the build writes anyway.

// Four float lanes: x, y, z and a spare (see Box).  The host is built for the x86-64 baseline
// (CMakeLists.txt sets no -m flags), of which SSE2 is part, so the binning below is SSE2; other
// targets take per-lane loops that compute the same values (host/bvh/NOTES.md, "SSE2 binning").
#if defined(__SSE2__)
using F4 = __m128;
inline F4 load4(const float* p) { return _mm_load_ps(p); }
inline void store4(float* p, F4 v) { _mm_store_ps(p, v); }
inline F4 set4(float x, float y, float z, float w) { return _mm_setr_ps(x, y, z, w); }
inline F4 add4(F4 a, F4 b) { return _mm_add_ps(a, b); }
inline F4 sub4(F4 a, F4 b) { return _mm_sub_ps(a, b); }
inline F4 mul4(F4 a, F4 b) { return _mm_mul_ps(a, b); }
// std::min(a, b) is (b < a ? b : a), std::max(a, b) is (a < b ? b : a); minps(x, y) is
// (x < y ? x : y) and maxps(x, y) is (x > y ? x : y).  Swapped operands make them the same
// function, so ties of -0 and +0 keep the zero the scalar builder kept: identical node boxes.
inline F4 min4(F4 a, F4 b) { return _mm_min_ps(b, a); }
inline F4 max4(F4 a, F4 b) { return _mm_max_ps(b, a); }
// All lanes' bits set if (int)x[A] < split (truncated as clamp_to_int4 does), else 0.
template <int A>
inline F4 below4(F4 x, int split) {
    const __m128i lt = _mm_cmplt_epi32(_mm_cvttps_epi32(x), _mm_set1_epi32(split));
    return _mm_castsi128_ps(_mm_shuffle_epi32(lt, _MM_SHUFFLE(A, A, A, A)));
}
inline F4 or4(F4 a, F4 b) { return _mm_or_ps(a, b); }
inline F4 not4(F4 a) { return _mm_xor_ps(a, _mm_castsi128_ps(_mm_set1_epi32(-1))); }
inline uint32_t bit0(F4 m) { return (uint32_t)_mm_movemask_ps(m) & 1u; }
// Lanes 0-2 of v, lane 3 all ones (NaN, which min4 and max4 ignore in their second operand).
inline F4 nan_w(F4 v) { return _mm_or_ps(v, _mm_castsi128_ps(_mm_setr_epi32(0, 0, 0, -1))); }
// v with the integer n added to the bits of lane 3 (lanes 0-2: + 0, unchanged bits).
inline F4 add_w(F4 v, uint32_t n) {
    return _mm_castsi128_ps(_mm_add_epi32(_mm_castps_si128(v), _mm_setr_epi32(0, 0, 0, (int)n)));
}
// Lanes 0-2 of p, lane 3 = 0.
inline F4 load_xyz(const float* p) {
    return _mm_and_ps(_mm_load_ps(p), _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0)));
}
// std::clamp((int)x, 0, top) per lane: cvttps2dq truncates as the scalar cast (cvttss2si) does.
inline void clamp_to_int4(F4 x, int top, int32_t out[4]) {
    __m128i k = _mm_cvttps_epi32(x);
    k = _mm_and_si128(k, _mm_cmpgt_epi32(k, _mm_setzero_si128()));
    const __m128i t = _mm_set1_epi32(top);
    const __m128i over = _mm_cmpgt_epi32(k, t);
    k = _mm_or_si128(_mm_and_si128(over, t), _mm_andnot_si128(over, k));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), k);
}
#else
struct F4 {
    float v[4];
};
inline F4 load4(const float* p) { return F4{{p[0], p[1], p[2], p[3]}}; }
inline void store4(float* p, F4 v) { std::memcpy(p, v.v, sizeof v.v); }
inline F4 set4(float x, float y, float z, float w) { return F4{{x, y, z, w}}; }
template <class Op>
inline F4 lanewise(F4 a, F4 b, Op op) {
    for (int k = 0; k < 4; ++k) a.v[k] = op(a.v[k], b.v[k]);
    return a;
}
inline F4 add4(F4 a, F4 b) { return lanewise(a, b, [](float x, float y) { return x + y; }); }
inline F4 sub4(F4 a, F4 b) { return lanewise(a, b, [](float x, float y) { return x - y; }); }
inline F4 mul4(F4 a, F4 b) { return lanewise(a, b, [](float x, float y) { return x * y; }); }
inline F4 min4(F4 a, F4 b) { return lanewise(a, b, [](float x, float y) { return std::min(x, y); }); }
inline F4 max4(F4 a, F4 b) { return lanewise(a, b, [](float x, float y) { return std::max(x, y); }); }
template <int A>
inline F4 below4(F4 x, int split) {
    const uint32_t m = (int)x.v[A] < split ? ~0u : 0u;
    F4 r;
    for (int k = 0; k < 4; ++k) std::memcpy(&r.v[k], &m, sizeof m);
    return r;
}
template <class Op>
inline F4 bitwise(F4 a, F4 b, Op op) {
    for (int k = 0; k < 4; ++k) {
        uint32_t x, y;
        std::memcpy(&x, &a.v[k], sizeof x);
        std::memcpy(&y, &b.v[k], sizeof y);
        x = op(x, y);
        std::memcpy(&a.v[k], &x, sizeof x);
    }
    return a;
}
inline F4 or4(F4 a, F4 b) { return bitwise(a, b, [](uint32_t x, uint32_t y) { return x | y; }); }
inline F4 not4(F4 a) { return bitwise(a, a, [](uint32_t x, uint32_t) { return ~x; }); }
inline uint32_t bit0(F4 m) {
    uint32_t x;
    std::memcpy(&x, &m.v[0], sizeof x);
    return x >> 31;
}
inline F4 nan_w(F4 v) {
    v.v[3] = NAN;
    return v;
}
inline F4 add_w(F4 v, uint32_t n) {
    uint32_t w;
    std::memcpy(&w, &v.v[3], sizeof w);
    w += n;
    std::memcpy(&v.v[3], &w, sizeof w);
    return v;
}
inline F4 load_xyz(const float* p) { return F4{{p[0], p[1], p[2], 0.0f}}; }
inline void clamp_to_int4(F4 x, int top, int32_t out[4]) {
    for (int k = 0; k < 4; ++k) out[k] = std::clamp((int)x.v[k], 0, top);
}
#endif

// Lanes 0-2 are x, y, z; lane 3 is no part of the box (0, except in the lo of a Ref and of a
// bin: see Ref and Bins), so growing is one min and one max of four lanes.
struct Box {
    alignas(16) float lo[4] = {INFINITY, INFINITY, INFINITY, 0.0f};
    alignas(16) float hi[4] = {-INFINITY, -INFINITY, -INFINITY, 0.0f};

    void grow(F4 blo, F4 bhi) {
        store4(lo, min4(load4(lo), blo));
        store4(hi, max4(load4(hi), bhi));
    }
    void grow(const Box& b) { grow(load4(b.lo), load4(b.hi)); }
    // For centroid bounds: grow_point(c, 0) of before, except that hi takes c where that took
    // c + 0 (+0 for a centroid of -0); cbounds.hi only enters as hi - lo > 0 (Builder::build),
    // which that zero's sign does not change.
    void grow_centroid(F4 c) { grow(c, c); }
    void grow_point(const float* p, float r) {
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], p[k] - r);
            hi[k] = std::max(hi[k], p[k] + r);
        }
    }
    bool empty() const { return !(lo[0] <= hi[0]); }
    // Half the surface area: SAH only needs ratios.
    double half_area() const {
        if (empty()) return 0.0;
        const double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
        return dx * dy + dy * dz + dz * dx;
    }
    float center(int k) const { return 0.5f * (lo[k] + hi[k]); }
};

// One BVH reference: a (piece of a) segment's box and, in the box's spare lane lo[3], the index
// of the segment in global order, so that a Ref is 32 bytes (as Embree's PrimRef): the binning
// and partition passes stream half the cache lines a 48-byte one would take.
struct Ref {
    Box box;
    uint32_t seg() const {
        uint32_t s;
        std::memcpy(&s, &box.lo[3], sizeof s);
        return s;
    }
    void set_seg(uint32_t s) { std::memcpy(&box.lo[3], &s, sizeof s); }
    // The box's lanes with lane 3 = 0 in lo (the index is no float to compute with).
    F4 lo4() const { return load_xyz(box.lo); }
    F4 hi4() const { return load4(box.hi); }
    // 0.5 (lo + hi) per lane, as Box::center.
    F4 center4() const { return mul4(set4(0.5f, 0.5f, 0.5f, 0.5f), add4(lo4(), hi4())); }
};
static_assert(sizeof(Ref) == 32, "Ref: the segment index lives in the box's spare lane");

// Intermediate node while building: both child slots as the final layout has them, children
// referring to intermediate node indices.
struct BNode {
    Box box[2];
    uint32_t child[2] = {0, 0};
    uint32_t count[2] = {0, 0};
    uint32_t begin = 0, end = 0;  // the node's references [begin, end): a subtree is contiguous
};

struct Slot {
    Box box;
    uint32_t child = 0, count = 0;  // count > 0: leaf [child, child + count) of the refs
};

// Binning scratch.  Reused per thread (thread_local in Builder::build) and reset for the bins
// in use only: initialising all kMax boxes of 3 axes for each of ~N/1.3 nodes cost about a
// quarter of the build.
// A bin's reference count is the integer in the spare lane of its box's lo (0 in Box()), so
// binning a reference writes two vectors per axis and no count: the binning was bound by its
// stores.  A positive count's bits are a positive float, never below the 0 of lane 3 of a box
// grown from bins, so grow() leaves that lane 0 and the boxes are as before.
struct Bins {
    static constexpr int kMax = 64;
    Box box[3][kMax];
    double right_cost[kMax];  // sweep scratch
    uint32_t right_n[kMax];
    void reset(int bins) {
        for (int a = 0; a < 3; ++a)
            for (int i = 0; i < bins; ++i) box[a][i] = Box();
    }
    uint32_t n(int a, int i) const {
        uint32_t c;
        std::memcpy(&c, &box[a][i].lo[3], sizeof c);
        return c;
    }
    // Adds a reference's box: lo is its lo with lane 3 NaN (nan_w), so the count's lane comes
    // from add_w alone.
    static void add(Box& bin, F4 lo, F4 hi, uint32_t count) {
        store4(bin.lo, min4(add_w(load4(bin.lo), count), lo));
        store4(bin.hi, max4(load4(bin.hi), hi));
    }
    void merge(const Bins& o, int bins) {
        for (int a = 0; a < 3; ++a)
            for (int i = 0; i < bins; ++i)
                add(box[a][i], nan_w(load4(o.box[a][i].lo)), load4(o.box[a][i].hi), o.n(a, i));
    }
};

// What the SAH charges c_isect for: the groups of leaf_lanes references a leaf of n is tested in.
double leaf_groups(uint32_t n, const BvhOptions& opt) {
    const uint32_t lanes = (uint32_t)std::max(1, opt.leaf_lanes);
    return (double)((n + lanes - 1) / lanes);
}

// What an oriented box must hold for one reference: its whole segment's capsule (even for a split
// reference's piece), the end points as stored (float, so nothing is lost; the boxes are computed
// in double) with their radii, a[3] = r_a and b[3] = r_b.  A triangle has b[3] < 0 (radii are
// positive, host/scene/hygiene.h) and no points here: no node holding one is oriented.  One array
// in the references' order, permuted with them by the build, serves the oriented splits and the
// flattening: filled before the build, it reads the segments in their order; gathered after it,
// in the leaves' order, it cost the ball's build 10-50 ms of cache misses (host/bvh/NOTES.md
// "Build time: the reference ends permuted with the references").
struct alignas(16) RefEnds {
    float a[4], b[4];
    bool triangle() const { return b[3] < 0.0f; }
    // 0.5 (r_a + r_b) exactly: at least the radius either precision intersects with
    double radius() const { return 0.5 * ((double)a[3] + (double)b[3]); }
};

// An affine frame p' = R (p - c): orthonormal rows, so boxes in it are as tight as the capsules.
struct Frame {
    double row[3][3];
    double c[3];
};

double dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

void normalize3(double* v) {
    const double l = std::sqrt(dot3(v, v));
    if (l > 0)
        for (int k = 0; k < 3; ++k) v[k] /= l;
}

void cross3(const double* a, const double* b, double* out) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

struct DBox {
    double lo[3] = {INFINITY, INFINITY, INFINITY};
    double hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double half_area() const {
        if (!(lo[0] <= hi[0])) return 0.0;
        const double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
        return dx * dy + dy * dz + dz * dx;
    }
};

// Sum of d d^T over a range's capsules (d = segment vector) and its triangle count: additive, so
// a node's is the sum of its children's (Flattener::moments_of) and each reference is read once.
// Trivial, so that the per-node array (Flattener::moments_of) is not zero-filled before it is
// written: value-initialise (Moments{}) where a sum starts.
struct Moments {
    double m[3][3];
    uint32_t triangles;
    void add(const Moments& o) {
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) m[j][k] += o.m[j][k];
        triangles += o.triangles;
    }
    // Adds d d^T of the segment from p0 to p1.
    void add_segment(const float* p0, const float* p1) {
        double d[3];
        for (int k = 0; k < 3; ++k) d[k] = (double)p1[k] - (double)p0[k];
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) m[j][k] += d[j] * d[k];
    }
};

Moments range_moments(const BulkVector<RefEnds>& ends, uint32_t b, uint32_t e) {
    Moments mo{};
    for (uint32_t i = b; i < e; ++i) {
        const RefEnds& q = ends[i];
        if (q.triangle()) {
            ++mo.triangles;
            continue;
        }
        mo.add_segment(q.a, q.b);
    }
    return mo;
}

// Whether a range's segment directions spread too widely for a frame along the dominant one to fit
// them better than the world axes: sum(lambda^2) < (sum lambda)^2 / 2 for the eigenvalues of sum d
// d^T (1 for one direction, 1/3 for directions all around; a cone of ~50 degrees gives 1/2).  Curls
// are (82 % of builtin:ball's children, none of the anchor strand's or straight.hair's); their
// frames took a quarter of the ball's oriented build and made 18 of its 14,040 nodes oriented
// (host/bvh/NOTES.md "Oriented nodes by default").
bool directions_spread(const Moments& mo) {
    const double (&m)[3][3] = mo.m;
    const double trace = m[0][0] + m[1][1] + m[2][2];
    double squares = 0;
    for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) squares += m[j][k] * m[j][k];
    return squares < 0.5 * trace * trace;
}

// The frame of a range with moments `mo`: first axis along the dominant segment direction
// (largest eigenvector of sum d d^T, so long segments weigh most and a strand's two directions
// count alike), the others across it.  False when no capsule has a direction.
bool dominant_frame(const Moments& mo, const Box& bounds, Frame& f) {
    const double (&m)[3][3] = mo.m;
    int big = 0;
    for (int k = 1; k < 3; ++k)
        if (m[k][k] > m[big][big]) big = k;
    if (!(m[big][big] > 0)) return false;
    // Power iteration on m^8 (three squarings, each scaled by its trace so that nothing overflows):
    // a step is eight of m's, so 4 steps reach what 32 of m's did.  Where no direction dominates
    // (curls) it never converges, and 32 steps of m took a quarter of the ball's oriented build
    // (host/bvh/NOTES.md "Oriented nodes by default").
    double q[3][3][3];
    const double (*src)[3] = m;
    for (int s = 0; s < 3; ++s) {
        double tr = 0;
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) {
                q[s][j][k] = src[j][0] * src[0][k] + src[j][1] * src[1][k] + src[j][2] * src[2][k];
                if (j == k) tr += q[s][j][k];
            }
        if (!(tr > 0)) return false;
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) q[s][j][k] /= tr;
        src = q[s];
    }
    const double (&m8)[3][3] = q[2];
    double v[3] = {m8[0][big], m8[1][big], m8[2][big]};
    normalize3(v);
    if (!(dot3(v, v) > 0)) return false;
    for (int it = 0; it < 4; ++it) {
        double w[3];
        for (int j = 0; j < 3; ++j) w[j] = dot3(m8[j], v);
        normalize3(w);
        if (!(dot3(w, w) > 0)) break;
        const double moved = std::fabs(w[0] - v[0]) + std::fabs(w[1] - v[1]) + std::fabs(w[2] - v[2]);
        for (int k = 0; k < 3; ++k) v[k] = w[k];
        if (moved < 1e-9) break;
    }
    // The second axis from the world axis least aligned with the first.
    int least = 0;
    for (int k = 1; k < 3; ++k)
        if (std::fabs(v[k]) < std::fabs(v[least])) least = k;
    double a[3] = {0, 0, 0};
    a[least] = 1;
    double u[3], w[3];
    cross3(v, a, u);
    normalize3(u);
    cross3(v, u, w);
    normalize3(w);
    for (int k = 0; k < 3; ++k) {
        f.row[0][k] = v[k];
        f.row[1][k] = u[k];
        f.row[2][k] = w[k];
        f.c[k] = 0.5 * ((double)bounds.lo[k] + (double)bounds.hi[k]);
    }
    return true;
}

class Builder {
public:
    // ends: null, or each reference's capsule (RefEnds) in the order of refs, which the builder
    // permutes with refs; oriented_splits: bin nodes in their segments' frame too (needs ends).
    Builder(BulkVector<Ref>& refs, const BvhOptions& opt, RefEnds* ends, bool oriented_splits)
        : refs_(refs), ends_(ends), split_oriented_(oriented_splits && ends), opt_(opt),
          bins_(std::clamp(opt.bins, 4, Bins::kMax)),
          lanes_((uint32_t)std::max(1, opt.leaf_lanes)), lane_shift_(-1) {
        for (int k = 0; k < 31; ++k)
            if (lanes_ == 1u << k) lane_shift_ = k;
        tokens_ = (int)build_threads(opt) - 1;
        // A binary tree over n references has at most n - 1 inner nodes (+1 for a leaf root).
        // Left uninitialised (place() constructs each node): a build uses about n / 5 of them
        // (leaves hold up to max_leaf references), and pages never written are never faulted
        // in; constructing all n (96 bytes each with 4-lane boxes) took a tenth of the build.
        storage_.reserve(std::max<size_t>(refs.size(), 1));
        mask_.reset(new uint64_t[refs.size() / 32 + 2]);  // see partition
        slots_ = storage_.data();
    }

    // Returns the intermediate root node index.
    uint32_t run() {
        if (refs_.empty()) return place(alloc(), BNode());  // both slots empty
        Box bounds, cbounds;
        bounds_of(0, (uint32_t)refs_.size(), bounds, cbounds);
        Slot top = build(0, (uint32_t)refs_.size(), bounds, cbounds, 1);
        if (top.count == 0) return top.child;
        BNode node;  // the whole scene is one leaf: root with one used slot
        node.box[0] = top.box;
        node.child[0] = top.child;
        node.count[0] = top.count;
        node.end = top.count;
        return place(alloc(), node);
    }

    // The nodes alloc() handed out: [0, used()).
    BNode* nodes() const { return std::launder(reinterpret_cast<BNode*>(slots_)); }
    uint32_t used() const { return used_.load(); }
    size_t oriented_splits() const { return oriented_splits_.load(); }

private:
    struct NodeStorage {
        alignas(BNode) unsigned char bytes[sizeof(BNode)];
    };
    static_assert(std::is_trivially_destructible<BNode>::value, "nodes are never destroyed");

    // A node's index is taken before its subtrees are built and the node is written once, by
    // place(), when they are done: constructing it in alloc() as well wrote each node twice, the
    // first time into a fresh cache line (~4 % of Builder::build in perf).
    uint32_t alloc() { return used_.fetch_add(1); }
    uint32_t place(uint32_t id, const BNode& node) {
        new (slots_ + id) BNode(node);
        return id;
    }

    void bounds_of(uint32_t b, uint32_t e, Box& bounds, Box& cbounds) const {
        for (uint32_t i = b; i < e; ++i) {
            bounds.grow(refs_[i].lo4(), refs_[i].hi4());
            cbounds.grow_centroid(refs_[i].center4());
        }
    }

    // The permutation std::partition gave (libstdc++'s Hoare loop: the next reference from the
    // left that goes right swaps with the next from the right that goes left), so the tree is the
    // same, without its branch per reference: on a strand's run of references the sides alternate
    // too irregularly for the branch predictor, and the mispredictions were most of its time in
    // perf.  Hoare's k-th swap pairs the k-th reference of [b, mid) that goes right with the k-th
    // of [mid, e), counted from the end, that goes left; a first pass writes each reference's side
    // to a bit mask, the second swaps the pairs the mask names.  The first pass also grows each
    // side's centroid bounds, with the centroid or NaN (min4(x, NaN) and max4(x, NaN) are x, as
    // minps and maxps return their second operand, here x, when either is NaN): that saves the
    // children's two centroid passes.  Min and max in another order than those passes' can differ
    // from theirs only in the sign of a zero, which no bin index or scale sees (see Box).
    //
    // A reference goes left if its centroid's bin on axis A, computed as bin_ref does but not
    // clamped, is below split (1 <= split <= nb - 1): clamping changes no side, as bins below 0
    // clamp to 0 < split, bins above nb - 1 to nb - 1 >= split, and cvttps2dq's 0x80000000 for
    // a value out of range is below split as its clamp to 0 is.
    template <int A>
    uint32_t partition(uint32_t b, uint32_t e, const Box& cbounds, const float* scale, int split, Box& cl,
                       Box& cr) {
        // Up to 64 references need one word, on the stack; a longer range [b, e) owns the words
        // of mask_ from b / 32 on: ceil(n / 64) of them fit below the next range's first word
        // for n >= 32, so the two threads' ranges never share a word.
        const uint32_t n = e - b;
        uint64_t one_word;
        uint64_t* const w = n <= 64 ? &one_word : mask_.get() + b / 32;
        const Ref* const r = refs_.data() + b;
        const F4 clo = load4(cbounds.lo), sc = load4(scale);
        F4 llo = load4(cl.lo), lhi = load4(cl.hi), rlo = load4(cr.lo), rhi = load4(cr.hi);
        uint32_t m = 0;  // references that go left
        for (uint32_t k0 = 0; k0 < n; k0 += 64) {
            const uint32_t k1 = std::min(n, k0 + 64);
            uint64_t word = 0;
            for (uint32_t k = k0; k < k1; ++k) {
                const F4 c = r[k].center4();
                const F4 left = below4<A>(mul4(sub4(c, clo), sc), split);
                const uint32_t bit = bit0(left);
                word |= uint64_t(bit) << (k - k0);
                m += bit;
                const F4 cl4 = or4(c, not4(left)), cr4 = or4(c, left);
                llo = min4(llo, cl4);
                lhi = max4(lhi, cl4);
                rlo = min4(rlo, cr4);
                rhi = max4(rhi, cr4);
            }
            w[k0 >> 6] = word;
        }
        store4(cl.lo, llo);
        store4(cl.hi, lhi);
        store4(cr.lo, rlo);
        store4(cr.hi, rhi);
        return swap_by_mask(b, n, w, m);
    }

    // The second half of the partition: w's bit k says reference b + k goes left, m of them do;
    // swaps Hoare's pairs.  Returns the first reference of the right side.
    uint32_t swap_by_mask(uint32_t b, uint32_t n, const uint64_t* w, uint32_t m) {
        if (m == 0 || m == n) return b + m;
        // Bits of word j: positions below m that go right, and positions from m on that go left.
        auto wrong_left = [&](uint32_t j) {
            const uint64_t go_right = ~w[j];
            return (j + 1) * 64 <= m ? go_right : go_right & ((uint64_t(1) << (m - j * 64)) - 1);
        };
        auto wrong_right = [&](uint32_t j) {
            return j * 64 >= m ? w[j] : w[j] & ~((uint64_t(1) << (m - j * 64)) - 1);
        };
        Ref* const out = refs_.data() + b;
        const uint32_t left_words = (m + 63) / 64;
        uint32_t jl = 0, jr = (n - 1) / 64;
        uint64_t bl = wrong_left(jl), br = wrong_right(jr);
        for (;;) {
            while (bl == 0) {
                if (++jl == left_words) return b + m;
                bl = wrong_left(jl);
            }
            while (br == 0) br = wrong_right(--jr);  // as many wrong on the right as on the left
            const uint32_t i = jl * 64 + (uint32_t)__builtin_ctzll(bl);
            bl &= bl - 1;
            const int top = 63 - __builtin_clzll(br);
            br &= ~(uint64_t(1) << top);
            std::swap(out[i], out[jr * 64 + (uint32_t)top]);
            if (ends_) std::swap(ends_[b + i], ends_[b + jr * 64 + (uint32_t)top]);
        }
    }

    // scale: 4 lanes, the last 0.  The bin of each axis is clamp((int)((c - lo) * scale)) of
    // the centroid c as in the partition's predicate, for the three axes at once.
    static void bin_ref(const Ref& r, F4 clo, F4 scale, int nb, Bins& out) {
        alignas(16) int32_t k[4];
        clamp_to_int4(mul4(sub4(r.center4(), clo), scale), nb - 1, k);
        const F4 lo = nan_w(load4(r.box.lo)), hi = r.hi4();
        for (int a = 0; a < 3; ++a) Bins::add(out.box[a][k[a]], lo, hi, 1);
    }

    // Consecutive references of a strand mostly fall in the same bins, so one pass is a chain
    // of load, min/max, store on the same bin boxes, each waiting for the previous store.  Two
    // contiguous halves binned in one loop into separate bins are two independent chains, and
    // merged in order they give the same boxes bit for bit: min/max that keep the first of equal
    // values (-0 and +0, see min4) give the first occurrence of the extreme whatever the
    // grouping of contiguous runs (the same holds for the two threads' halves in build()).
    void bin_range(uint32_t b, uint32_t e, const Box& cb, const float* scale, int nb,
                   Bins& out) const {
        const F4 clo = load4(cb.lo), sc = load4(scale);
        const uint32_t half = (e - b) / 2;
        if (half < kTwoChainsFrom) {
            for (uint32_t i = b; i < e; ++i) bin_ref(refs_[i], clo, sc, nb, out);
            return;
        }
        thread_local Bins second_half;
        second_half.reset(nb);
        const uint32_t mid = b + half;
        for (uint32_t i = b; i < mid; ++i) {
            bin_ref(refs_[i], clo, sc, nb, out);
            bin_ref(refs_[i + half], clo, sc, nb, second_half);
        }
        if (mid + half < e) bin_ref(refs_[e - 1], clo, sc, nb, second_half);
        out.merge(second_half, nb);
    }
    static constexpr uint32_t kTwoChainsFrom = 64;  // references per half

    bool take_token() {
        int t = tokens_.load();
        while (t > 0)
            if (tokens_.compare_exchange_weak(t, t - 1)) return true;
        return false;
    }
    void give_token() { tokens_.fetch_add(1); }

    Slot leaf(uint32_t b, uint32_t e, const Box& bounds) {
        Slot s;
        s.box = bounds;
        s.child = b;
        s.count = e - b;
        return s;
    }

    // leaf_groups without its division: the sweep asks for two group counts per candidate plane,
    // and a 32-bit div per count was a visible share of Builder::build in perf.
    double groups(uint32_t n) const {
        return lane_shift_ >= 0 ? (double)((n + lanes_ - 1) >> lane_shift_) : leaf_groups(n, opt_);
    }

    struct Split {
        double cost = INFINITY;
        int axis = -1, split = 0;  // left: the bins below `split` on `axis`
    };

    // The best SAH plane of binned references: axes with scale 0 (no centroid extent) are skipped.
    void sweep(Bins& bins, int nb, const float* scale, double isect_per_area, Split& best) const {
        for (int a = 0; a < 3; ++a) {
            if (scale[a] == 0.0f) continue;
            // The right side's area x groups per plane, as the cost below would compute it.
            double* right_cost = bins.right_cost;
            uint32_t* right_n = bins.right_n;
            Box acc;
            uint32_t cnt = 0;
            for (int i = nb - 1; i > 0; --i) {
                acc.grow(bins.box[a][i]);
                cnt += bins.n(a, i);
                right_cost[i] = acc.half_area() * groups(cnt);
                right_n[i] = cnt;
            }
            Box left;
            uint32_t ln = 0;
            for (int i = 1; i < nb; ++i) {
                left.grow(bins.box[a][i - 1]);
                ln += bins.n(a, i - 1);
                if (ln == 0 || right_n[i] == 0) continue;
                const double cost = opt_.c_trav + isect_per_area * (left.half_area() * groups(ln) + right_cost[i]);
                if (cost < best.cost) {
                    best.cost = cost;
                    best.axis = a;
                    best.split = i;
                }
            }
        }
    }

    // Oriented split (BvhOptions::obb_split): the references binned again in the frame of their
    // dominant direction (dominant_frame), their boxes there being what an oriented node would
    // test.  Where that split's area x groups is below obb_split x the axis-aligned best's, the
    // range is partitioned by it and true is returned with the first right reference in `mid`.
    // Bundles of parallel fibres across the axes are then cut along and across the fibres, not
    // into diagonal slices (host/bvh/NOTES.md "Oriented splits").
    bool oriented_split(uint32_t b, uint32_t e, const Box& bounds, int nb, double isect_per_area,
                        double aligned_cost, uint32_t& mid) {
        const uint32_t n = e - b;
        // The frame from at most 511 references spread evenly over the range: a direction is all
        // it needs, and reading every reference's end points twice cost a quarter of the build.
        Moments mo{};
        const uint32_t stride = std::max(1u, n / 256);
        for (uint32_t i = b; i < e; i += stride) mo.add_segment(ends_[i].a, ends_[i].b);
        Frame f;
        if (!dominant_frame(mo, bounds, f)) return false;
        float row[3][3], c[3];
        for (int j = 0; j < 3; ++j) {
            c[j] = (float)f.c[j];
            for (int k = 0; k < 3; ++k) row[j][k] = (float)f.row[j][k];
        }
        // A Ref for its lane-3-free centroid; its spare lane keeps the centroid's three bins
        // (below), which the partition reads back instead of computing them again.
        thread_local std::vector<Ref> fbox;
        fbox.resize(n);
        Box cb;
        for (uint32_t i = 0; i < n; ++i) {
            const RefEnds& q = ends_[b + i];
            F4 x[2];
            for (int v = 0; v < 2; ++v) {
                const float* e = v ? q.b : q.a;
                const float p[3] = {e[0] - c[0], e[1] - c[1], e[2] - c[2]};
                x[v] = set4(row[0][0] * p[0] + row[0][1] * p[1] + row[0][2] * p[2],
                            row[1][0] * p[0] + row[1][1] * p[1] + row[1][2] * p[2],
                            row[2][0] * p[0] + row[2][1] * p[1] + row[2][2] * p[2], 0.0f);
            }
            // In registers, stored once: growing the stored box lane by lane and reading it back
            // as a vector stalled on the stores.
            const float r = 0.5f * (q.a[3] + q.b[3]);
            const F4 rr = set4(r, r, r, 0.0f);
            const F4 lo = sub4(min4(x[0], x[1]), rr), hi = add4(max4(x[0], x[1]), rr);
            store4(fbox[i].box.lo, lo);
            store4(fbox[i].box.hi, hi);
            const F4 centre = mul4(set4(0.5f, 0.5f, 0.5f, 0.5f), add4(lo, hi));
            cb.grow_centroid(centre);
        }
        alignas(16) float scale[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        for (int a = 0; a < 3; ++a) {
            const float ext = cb.hi[a] - cb.lo[a];
            scale[a] = ext > 0 ? (float)nb * (1.0f - 1e-6f) / ext : 0.0f;
        }
        const F4 clo = load4(cb.lo), sc = load4(scale);
        thread_local Bins obins;
        obins.reset(nb);
        alignas(16) int32_t k[4];
        for (uint32_t i = 0; i < n; ++i) {
            clamp_to_int4(mul4(sub4(fbox[i].center4(), clo), sc), nb - 1, k);
            const F4 lo = nan_w(load4(fbox[i].box.lo)), hi = fbox[i].hi4();
            for (int a = 0; a < 3; ++a) Bins::add(obins.box[a][k[a]], lo, hi, 1);
            static_assert(Bins::kMax <= 256, "a bin index fits 8 bits");
            fbox[i].set_seg(uint32_t(k[0]) | uint32_t(k[1]) << 8 | uint32_t(k[2]) << 16);
        }
        Split os;
        sweep(obins, nb, scale, isect_per_area, os);
        if (os.axis < 0 || !(os.cost - opt_.c_trav < opt_.obb_split * (aligned_cost - opt_.c_trav))) return false;
        uint64_t one_word;
        uint64_t* const w = n <= 64 ? &one_word : mask_.get() + b / 32;
        uint32_t m = 0;
        for (uint32_t k0 = 0; k0 < n; k0 += 64) {
            uint64_t word = 0;
            for (uint32_t i = k0; i < std::min(n, k0 + 64); ++i) {
                const int bin = int(fbox[i].seg() >> (8 * os.axis) & 255u);
                const uint32_t bit = bin < os.split ? 1u : 0u;
                word |= uint64_t(bit) << (i - k0);
                m += bit;
            }
            w[k0 >> 6] = word;
        }
        mid = swap_by_mask(b, n, w, m);
        oriented_splits_.fetch_add(1, std::memory_order_relaxed);
        return true;  // the sweep only takes planes with references on both sides
    }

    Slot build(uint32_t b, uint32_t e, const Box& bounds, const Box& cbounds, int depth) {
        const uint32_t n = e - b;
        const double leaf_cost = opt_.c_isect * groups(n);
        if (n == 1 || depth >= kMaxBvhDepth) return leaf(b, e, bounds);
        // Every split costs at least c_trav (areas and groups are not negative), so when a leaf
        // costs no more, the leaf test after the sweep takes the leaf: the compact() preset's
        // nodes of up to max_leaf need no binning.
        if (n <= (uint32_t)opt_.max_leaf && opt_.c_isect >= 0 && leaf_cost <= opt_.c_trav) return leaf(b, e, bounds);

        // ---- binning (two threads for the big top-level ranges)
        // Small nodes get fewer bins: the SAH sweep is O(bins) per axis and dominated the
        // build for the ~N/2 nodes near the leaves, where n bins resolve as much as 16.
        const int nb = std::min(bins_, std::max(4, (int)n));
        alignas(16) float scale[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        for (int a = 0; a < 3; ++a) {
            const float ext = cbounds.hi[a] - cbounds.lo[a];
            scale[a] = ext > 0 ? (float)nb * (1.0f - 1e-6f) / ext : 0.0f;
        }
        thread_local Bins scratch;
        Bins& bins = scratch;
        bins.reset(nb);
        if (n >= 65536 && take_token()) {
            std::unique_ptr<Bins> other_ptr(new Bins);
            Bins& other = *other_ptr;
            other.reset(nb);
            const uint32_t mid = b + n / 2;
            std::thread th([&] { bin_range(mid, e, cbounds, scale, nb, other); });
            bin_range(b, mid, cbounds, scale, nb, bins);
            th.join();
            give_token();
            bins.merge(other, nb);
        } else {
            bin_range(b, e, cbounds, scale, nb, bins);
        }

        // ---- best SAH plane over all axes
        const double inv_area = 1.0 / std::max(bounds.half_area(), 1e-30);
        const double isect_per_area = opt_.c_isect * inv_area;
        Split best;
        sweep(bins, nb, scale, isect_per_area, best);
        const double best_cost = best.cost;
        const int best_axis = best.axis, best_split = best.split;
        Box best_l, best_r;
        // The winner's boxes, grown in the sweeps' order: copying them at each better plane was a
        // store of two boxes per improvement in the sweep.
        if (best_axis >= 0) {
            for (int i = 0; i < best_split; ++i) best_l.grow(bins.box[best_axis][i]);
            for (int i = nb - 1; i >= best_split; --i) best_r.grow(bins.box[best_axis][i]);
        }

        if (n <= (uint32_t)opt_.max_leaf && leaf_cost <= best_cost) return leaf(b, e, bounds);

        uint32_t mid;
        Box cl, cr;
        if (split_oriented_ && best_axis >= 0 && n >= kOrientedSplitFrom &&
            oriented_split(b, e, bounds, nb, isect_per_area, best_cost, mid)) {
            best_l = Box();
            best_r = Box();
            bounds_of(b, mid, best_l, cl);
            bounds_of(mid, e, best_r, cr);
        } else if (best_axis >= 0) {
            mid = best_axis == 0 ? partition<0>(b, e, cbounds, scale, best_split, cl, cr)
                : best_axis == 1 ? partition<1>(b, e, cbounds, scale, best_split, cl, cr)
                                 : partition<2>(b, e, cbounds, scale, best_split, cl, cr);
        } else {
            // All centroids coincide (duplicated or split pieces): halve the range.
            mid = b + n / 2;
            best_l = Box();
            best_r = Box();
            bounds_of(b, mid, best_l, cl);
            bounds_of(mid, e, best_r, cr);
        }

        const uint32_t id = alloc();
        Slot left, right;
        if (n >= 4096 && take_token()) {
            // A token is a thread free to take a subtree.  Each side hands its token back as soon
            // as its own subtree is done, not at the join: the subtrees of an uneven split
            // finish apart, and the one still running can split off work to the idle thread.
            std::thread th([&] {
                left = build(b, mid, best_l, cl, depth + 1);
                give_token();
            });
            right = build(mid, e, best_r, cr, depth + 1);
            give_token();
            th.join();
            tokens_.fetch_sub(1);  // this thread runs on (the other one has given its token back)
        } else {
            left = build(b, mid, best_l, cl, depth + 1);
            right = build(mid, e, best_r, cr, depth + 1);
        }
        place(id, BNode{{left.box, right.box}, {left.child, right.child}, {left.count, right.count}, b, e});
        Slot s;
        s.box = bounds;
        s.child = id;
        s.count = 0;
        return s;
    }

    // Nodes this small are split axis-aligned only: an oriented split pays for a whole subtree.
    static constexpr uint32_t kOrientedSplitFrom = 16;

    BulkVector<Ref>& refs_;
    RefEnds* ends_ = nullptr;  // per reference, permuted with refs_, or null
    bool split_oriented_ = false;  // oriented_split() considered
    BulkVector<NodeStorage> storage_;  // reserved, never resized: alloc() hands out its slots
    std::unique_ptr<uint64_t[]> mask_;  // partition's side bits
    NodeStorage* slots_ = nullptr;     // storage_.data()
    BvhOptions opt_;
    int bins_;
    uint32_t lanes_;   // max(1, opt_.leaf_lanes)
    int lane_shift_;   // log2(lanes_) if a power of two, else -1
    std::atomic<int> tokens_{0};
    std::atomic<uint32_t> used_{0};
    std::atomic<size_t> oriented_splits_{0};
};

// Box of references [b, e) in frame f: a capsule's extent along a unit axis is its end points'
// extent widened by r.
// With stride > 1, of every stride-th reference only: a box inside the full one.
// Capsules only (a range with a triangle is never oriented).
DBox frame_box(const BulkVector<RefEnds>& ends, uint32_t b, uint32_t e, const Frame& f, uint32_t stride = 1) {
    DBox box;
#if defined(__SSE2__)
    // A capsule's two end points in the two double lanes: each lane's products and sums in the
    // scalar loop's order (the same coordinates bit for bit), the running bounds kept per lane and
    // joined at the end.  A minimum or maximum taken in another order could differ only in the sign
    // of a zero, and x - r and x + r are never -0 (r > 0; an exact zero of a sum is +0).  Each
    // operation serves both end points (the scalar loop was inlined into Flattener::visit, whose own
    // samples were 11 % of straight.hair's build: host/bvh/NOTES.md "Build time: the oriented boxes
    // in two lanes").
    __m128d c[3], row[3][3], lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
        c[k] = _mm_set1_pd(f.c[k]);
        for (int j = 0; j < 3; ++j) row[j][k] = _mm_set1_pd(f.row[j][k]);
        lo[k] = _mm_set1_pd(INFINITY);
        hi[k] = _mm_set1_pd(-INFINITY);
    }
    for (uint32_t i = b; i < e; i += stride) {
        const RefEnds& q = ends[i];
        const __m128 pa = _mm_load_ps(q.a), pb = _mm_load_ps(q.b);
        const __m128 ab01 = _mm_unpacklo_ps(pa, pb), ab23 = _mm_unpackhi_ps(pa, pb);  // a0 b0 a1 b1, a2 b2 r_a r_b
        const __m128d p[3] = {_mm_sub_pd(_mm_cvtps_pd(ab01), c[0]), _mm_sub_pd(_mm_cvtps_pd(_mm_movehl_ps(ab01, ab01)), c[1]),
                              _mm_sub_pd(_mm_cvtps_pd(ab23), c[2])};
        const __m128d r = _mm_set1_pd(q.radius());
        for (int j = 0; j < 3; ++j) {
            const __m128d x = _mm_add_pd(_mm_add_pd(_mm_mul_pd(row[j][0], p[0]), _mm_mul_pd(row[j][1], p[1])),
                                         _mm_mul_pd(row[j][2], p[2]));
            lo[j] = _mm_min_pd(_mm_sub_pd(x, r), lo[j]);  // std::min(lo, x - r)
            hi[j] = _mm_max_pd(_mm_add_pd(x, r), hi[j]);  // std::max(hi, x + r)
        }
    }
    for (int j = 0; j < 3; ++j) {
        alignas(16) double l[2], h[2];
        _mm_store_pd(l, lo[j]);
        _mm_store_pd(h, hi[j]);
        box.lo[j] = std::min(l[0], l[1]);
        box.hi[j] = std::max(h[0], h[1]);
    }
#else
    for (uint32_t i = b; i < e; i += stride) {
        const RefEnds& q = ends[i];
        const double r = q.radius();
        for (const float* v : {q.a, q.b}) {
            const double p[3] = {(double)v[0] - f.c[0], (double)v[1] - f.c[1], (double)v[2] - f.c[2]};
            for (int j = 0; j < 3; ++j) {
                const double x = dot3(f.row[j], p);
                box.lo[j] = std::min(box.lo[j], x - r);
                box.hi[j] = std::max(box.hi[j], x + r);
            }
        }
    }
#endif
    return box;
}

// The world axes as a frame (a child without a direction in an oriented node).
void axis_frame(const Box& bounds, Frame& f) {
    for (int j = 0; j < 3; ++j) {
        for (int k = 0; k < 3; ++k) f.row[j][k] = j == k ? 1.0 : 0.0;
        f.c[j] = 0.5 * ((double)bounds.lo[j] + (double)bounds.hi[j]);
    }
}

// The size of the coordinates the kernel computes with for this box: the frame's centre plus the
// box's own reach from it.
double magnitude(const Frame& f, const DBox& b) {
    double m = 0;
    for (int k = 0; k < 3; ++k)
        m = std::max({m, std::fabs(f.c[k]), std::fabs(b.lo[k]), std::fabs(b.hi[k])});
    return m;
}

// Oriented bounds are widened by 2^-19 of that magnitude: the map is stored in float and the
// kernel applies it in float (rounding ~ulp(|p|) per product, ~30x less than this), and a box
// must never cut a capsule off.
void pad_outward(const Frame& f, DBox& b) {
    const double pad = std::ldexp(magnitude(f, b), -19);
    for (int k = 0; k < 3; ++k) {
        b.lo[k] -= pad;
        b.hi[k] += pad;
    }
}

// Binary build tree -> 8-wide nodes, depth-first preorder.  A node first opens its binary node's
// subtree kCollapseLevels = 3 levels deep (a leaf met on the way stays a leaf slot), which the
// stack bound above relies on; while that leaves slots free, the inner slot with the largest box
// is opened further (Embree's and Cycles' greedy collapse, here only below the three levels, so
// the depth bound holds).  Slots stay in the binary tree's left-to-right order.
struct Flattener {
    const BNode* in;  // Builder::nodes()
    // Records [next, end) of out are this flattener's to fill, in preorder (records_below() bounds
    // what a subtree needs).
    HtBvhNode* out;
    uint32_t next, end;
    const BvhOptions& opt;
    const BulkVector<RefEnds>& ends;
    const BulkVector<Moments>& moments;  // per intermediate node (moments_of)
    unsigned threads = 1;
    double root_area = 1;
    double sah = 0;
    size_t leaves = 0, max_depth = 0, oriented = 0;

    static constexpr int W = HT_BVH_WIDTH;

    // The (up to W) children of the 8-wide node made of intermediate node id: kCollapseLevels full
    // binary levels, then the inner slot of largest area opened until there are W.  Returns their
    // number.
    static int collapse(const BNode* in, uint32_t id, Slot* slot) {
        const BNode& bn = in[id];
        int level[W];  // binary levels below `id`
        int m = 0;
        // Replaces slot i (inner) by its binary node's children.
        auto open = [&](int i) {
            const BNode& g = in[slot[i].child];
            Slot kids[2];
            int nk = 0;
            for (int t = 0; t < 2; ++t)
                if (g.count[t] != 0 || g.child[t] != 0) kids[nk++] = Slot{g.box[t], g.child[t], g.count[t]};
            const int lv = level[i] + 1;
            std::copy_backward(slot + i + 1, slot + m, slot + m + nk - 1);
            std::copy_backward(level + i + 1, level + m, level + m + nk - 1);
            for (int t = 0; t < nk; ++t) slot[i + t] = kids[t], level[i + t] = lv;
            m += nk - 1;
        };
        for (int s = 0; s < 2; ++s)
            if (bn.count[s] != 0 || bn.child[s] != 0)  // else empty (0- or 1-segment scene)
                slot[m] = Slot{bn.box[s], bn.child[s], bn.count[s]}, level[m++] = 1;
        for (int i = 0; i < m;)  // full levels: at most 2^3 = W slots
            if (slot[i].count == 0 && level[i] < kCollapseLevels)
                open(i);
            else
                ++i;
        while (m < W) {
            int pick = -1;
            double best = -1;
            for (int i = 0; i < m; ++i)
                if (slot[i].count == 0 && slot[i].box.half_area() > best) pick = i, best = slot[i].box.half_area();
            if (pick < 0) break;
            open(pick);
        }
        return m;
    }

    // Records the 8-wide subtree of intermediate node id can take: one per node, two if oriented
    // (a parallel part's range; the whole output is bounded by the binary node count instead, so
    // that the tree is counted once).
    static size_t records_below(const BNode* in, uint32_t id, bool oriented) {
        Slot slot[W];
        const int m = collapse(in, id, slot);
        size_t n = oriented ? 2 : 1;
        for (int k = 0; k < m; ++k)
            if (slot[k].count == 0) n += records_below(in, slot[k].child, oriented);
        return n;
    }

    // The next record, zeroed (it is written before any of its children's, so preorder).
    uint32_t take() {
        if (next >= end) throw std::logic_error("BVH: flattening overran its records");
        out[next] = HtBvhNode{};
        return next++;
    }

    // Returns the reference (output index | HT_NODE_ORIENTED) of intermediate node `id`, whose box
    // as its parent tests it has half-area `area`.
    uint32_t visit(uint32_t id, size_t depth, double area) {
        const uint32_t me = take();
        max_depth = std::max(max_depth, depth);
        Slot slot[W];
        const int m = collapse(in, id, slot);
        uint32_t range[W][2];
        for (int k = 0; k < m; ++k) {
            range[k][0] = slot[k].count > 0 ? slot[k].child : in[slot[k].child].begin;
            range[k][1] = slot[k].count > 0 ? slot[k].child + slot[k].count : in[slot[k].child].end;
        }
        sah += opt.c_trav * area / root_area;

        // Oriented or axis-aligned: the children's boxes weighted by what they hold (the SAH's
        // expected cost below them, to first order), oriented only if clearly smaller, since
        // mapping the ray per child costs about twice the axis-aligned test.  The root stays
        // axis-aligned; so do nodes with triangles (flat boxes have no unit-cube map).
        Frame frame[W];
        bool world[W];  // frame[k] is the world axes
        bool boxed[W];  // obox[k] is child k's full frame box already (unpadded)
        DBox obox[W];
        bool orient = depth > 0 && opt.obb_ratio > 0 && m > 0;
        double aligned = 0, turned = 0;
        for (int k = 0; k < m && orient; ++k) aligned += double(range[k][1] - range[k][0]) * slot[k].box.half_area();
        for (int k = 0; k < m && orient; ++k) {
            const Moments mo = slot[k].count ? range_moments(ends, range[k][0], range[k][1]) : moments[slot[k].child];
            orient = mo.triangles == 0;
            if (!orient) break;
            world[k] = directions_spread(mo) || !dominant_frame(mo, slot[k].box, frame[k]);
            if (world[k]) axis_frame(slot[k].box, frame[k]);
        }
        // Where the boxes of a sample of each child's capsules (inside the full boxes, so a lower
        // bound) already reach the threshold, the node stays axis-aligned without the full boxes:
        // the same decision, and most of the oriented build's time on scenes whose nodes rarely
        // qualify (curls: builtin:ball, host/bvh/NOTES.md "Oriented nodes by default").
        // A child of fewer than 2 x kBoundSample references is sampled whole: its box is kept.
        for (int k = 0; k < m && orient; ++k) {
            const uint32_t n = range[k][1] - range[k][0], stride = std::max(1u, n / kBoundSample);
            boxed[k] = !world[k] && stride == 1;
            if (world[k]) {  // in the world axes the box is the child's own (shrunk by float rounding's worth)
                turned += double(n) * slot[k].box.half_area() * (1 - 1e-5);
                continue;
            }
            const DBox sample = frame_box(ends, range[k][0], range[k][1], frame[k], stride);
            if (boxed[k]) obox[k] = sample;
            turned += double(n) * sample.half_area();
        }
        orient = orient && turned < opt.obb_ratio * aligned;
        turned = 0;
        for (int k = 0; k < m && orient; ++k) {
            if (!boxed[k]) obox[k] = frame_box(ends, range[k][0], range[k][1], frame[k]);
            pad_outward(frame[k], obox[k]);
            for (int j = 0; j < 3; ++j)
                orient = orient && obox[k].hi[j] - obox[k].lo[j] > 0x1p-40 * (1.0 + magnitude(frame[k], obox[k]));
            turned += double(range[k][1] - range[k][0]) * obox[k].half_area();
        }
        orient = orient && turned < opt.obb_ratio * aligned;
        double child_area[W];
        for (int k = 0; k < m; ++k) child_area[k] = orient ? obox[k].half_area() : slot[k].box.half_area();
        if (orient) {
            ++oriented;
            take();
        }

        uint32_t child[W] = {};
        // With oriented nodes the root's subtrees are flattened on all build threads (the oriented
        // boxes cost as much as the binary build), each into records of its own after the ones
        // before it (records_below), then moved together in order: the same preorder and the same
        // records as one thread writes.  Axis-aligned nodes cost less to write than that move:
        // one thread writes them in place (ball, 2 threads: ~2 ms instead of ~4).
        const bool parallel = depth == 0 && threads > 1 && opt.obb_ratio > 0;
        std::vector<Flattener> sub;
        uint32_t first[W] = {};
        if (parallel) {
            uint32_t at = next;
            for (int k = 0; k < m; ++k) {
                const size_t need = slot[k].count == 0 ? records_below(in, slot[k].child, true) : 0;
                if (need > end - at) throw std::logic_error("BVH: flattening overran its records");
                first[k] = at;
                sub.push_back(Flattener{in, out, at, at + (uint32_t)need, opt, ends, moments, threads, root_area});
                at += (uint32_t)need;
            }
            std::atomic<int> turn{0};
            auto work = [&] {
                for (int k; (k = turn++) < m;)
                    if (slot[k].count == 0) child[k] = sub[k].visit(slot[k].child, depth + 1, child_area[k]);
            };
            std::vector<std::thread> pool;
            for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
            work();
            for (std::thread& t : pool) t.join();
        }
        for (int k = 0; k < m; ++k) {
            if (slot[k].count > 0) {
                child[k] = slot[k].child;
                ++leaves;
                max_depth = std::max(max_depth, depth + 1);
                sah += opt.c_isect * leaf_groups(slot[k].count, opt) * child_area[k] / root_area;
            } else if (parallel) {
                const uint32_t used = sub[k].next - first[k], shift = first[k] - next;
                if (shift > 0) {
                    std::memmove(out + next, out + first[k], size_t(used) * sizeof(HtBvhNode));
                    child[k] -= shift;  // keeps HT_NODE_ORIENTED
                    relocate(out, child[k], shift);
                }
                next += used;
                sah += sub[k].sah;
                leaves += sub[k].leaves;
                oriented += sub[k].oriented;
                max_depth = std::max(max_depth, sub[k].max_depth);
            } else {
                child[k] = visit(slot[k].child, depth + 1, child_area[k]);
            }
        }
        HtBvhNode& n = out[me];
        for (int k = 0; k < W; ++k) {
            const bool used = k < m;
            n.child[k] = child[k];
            n.count[k] = used ? slot[k].count : 0u;
            if (orient) continue;
            for (int a = 0; a < 3; ++a) {
                float* axis = a == 0 ? n.x : a == 1 ? n.y : n.z;
                axis[k] = used ? slot[k].box.lo[a] : 0.0f;
                axis[k + W] = used ? slot[k].box.hi[a] : 0.0f;
            }
        }
        if (orient) {
            // coefficient c of child k at [W * (c & 1) + k] of the c / 2-th array (kernels/types.h)
            HtBvhNode& f = out[me + 1];
            float* arrays[6] = {n.x, n.y, n.z, f.x, f.y, f.z};
            for (float* a : arrays) std::fill(a, a + 2 * W, 0.0f);
            for (int k = 0; k < m; ++k)
                for (int j = 0; j < 3; ++j) {
                    const double s = 1.0 / (obox[k].hi[j] - obox[k].lo[j]);
                    const double coef[4] = {frame[k].row[j][0] * s, frame[k].row[j][1] * s, frame[k].row[j][2] * s,
                                            (-dot3(frame[k].row[j], frame[k].c) - obox[k].lo[j]) * s};
                    for (int c = 0; c < 4; ++c) {
                        const int cc = 4 * j + c;
                        arrays[cc / 2][W * (cc & 1) + k] = (float)coef[c];
                    }
                }
        }
        return orient ? me | HT_NODE_ORIENTED : me;
    }

    // Fills out[id] with the moments of intermediate node id's references, bottom-up; with two
    // threads or more (the build passes one for small trees), the root's second subtree on a thread
    // of its own (the same sums in the same order: the serial pass was ~1.4 ms of straight.hair's
    // build, host/bvh/NOTES.md "Build time: the oriented boxes in two lanes").
    static const Moments& moments_of(const BNode* in, const BulkVector<RefEnds>& ends, uint32_t id,
                                     BulkVector<Moments>& out, unsigned threads = 1) {
        const BNode& bn = in[id];
        const bool inner[2] = {bn.count[0] == 0 && bn.child[0] != 0, bn.count[1] == 0 && bn.child[1] != 0};
        std::thread second;
        if (threads > 1 && inner[0] && inner[1]) second = std::thread([&] { moments_of(in, ends, bn.child[1], out); });
        Moments mo{};
        for (int s = 0; s < 2; ++s) {
            if (bn.count[s] > 0) {
                mo.add(range_moments(ends, bn.child[s], bn.child[s] + bn.count[s]));
            } else if (s == 1 && second.joinable()) {
                second.join();
                mo.add(out[bn.child[1]]);
            } else if (inner[s]) {
                mo.add(moments_of(in, ends, bn.child[s], out));
            }
        }
        return out[id] = mo;
    }

    // Takes `shift` off the inner child references below node `ref` of a subtree moved down by
    // that many records.
    static void relocate(HtBvhNode* v, uint32_t ref, uint32_t shift) {
        HtBvhNode& n = v[ref & ~HT_NODE_ORIENTED];
        for (int k = 0; k < HT_BVH_WIDTH; ++k)
            if (n.count[k] == 0 && n.child[k] != 0) {
                n.child[k] -= shift;
                relocate(v, n.child[k], shift);
            }
    }
};

// Box of the capsule piece between parameters [a, b] of the segment, split while it pays.
void add_refs(BulkVector<Ref>& refs, uint32_t seg, const float* p0, const float* p1, float r,
              float a, float b, int depth, const BvhOptions& opt) {
    float pa[3], pb[3];
    for (int k = 0; k < 3; ++k) {
        pa[k] = p0[k] + (p1[k] - p0[k]) * a;
        pb[k] = p0[k] + (p1[k] - p0[k]) * b;
    }
    Ref ref;
    ref.box.grow_point(pa, r);
    ref.box.grow_point(pb, r);
    ref.set_seg(seg);
    if (opt.split_ratio > 0 && depth < opt.split_depth) {
        const float m = 0.5f * (a + b);
        float pm[3];
        for (int k = 0; k < 3; ++k) pm[k] = p0[k] + (p1[k] - p0[k]) * m;
        Box h1, h2;
        h1.grow_point(pa, r);
        h1.grow_point(pm, r);
        h2.grow_point(pm, r);
        h2.grow_point(pb, r);
        if (h1.half_area() + h2.half_area() < opt.split_ratio * ref.box.half_area()) {
            add_refs(refs, seg, p0, p1, r, a, m, depth + 1, opt);
            add_refs(refs, seg, p0, p1, r, m, b, depth + 1, opt);
            return;
        }
    }
    refs.push_back(ref);
}

// fn(b, e) over [0, n) on pass_threads(n, threads) threads (core/parallel.h).
template <class Fn>
void for_ranges(size_t n, unsigned threads, const Fn& fn) {
    in_parallel(n, int(pass_threads(n, threads)), [&](int, size_t b, size_t e) { fn(b, e); });
}

void build_bvh_from(const BulkVector<HtSegment>& base, SceneGeometry& geo, const BvhOptions& opt) {
    const unsigned threads = build_threads(opt);
    BulkVector<Ref> refs;
    refs.reserve(base.size());
    for (uint32_t i = 0; i < base.size(); ++i) {
        if (ht_seg_flags(base[i]) & HT_SEG_TRIANGLE) {
            // Triangles are never split: their boxes are tight already for mesh-like shapes.
            Ref ref;
            ref.set_seg(i);
            for (uint32_t v = 0; v < 3; ++v) {
                const HtPoint& p = geo.points[base[i].point + v];
                const float pv[3] = {p.x, p.y, p.z};
                ref.box.grow_point(pv, 0.0f);
            }
            refs.push_back(ref);
            continue;
        }
        const HtPoint& a = geo.points[base[i].point];
        const HtPoint& b = geo.points[base[i].point + 1];
        const float p0[3] = {a.x, a.y, a.z}, p1[3] = {b.x, b.y, b.z};
        add_refs(refs, i, p0, p1, 0.5f * (a.r + b.r), 0.0f, 1.0f, 0, opt);
    }

    // Each reference's end points for the oriented nodes and splits (RefEnds), filled in the
    // segments' order and permuted with the references by the build.
    BulkVector<RefEnds> ends;
    if (opt.obb_ratio > 0) {
        ends.resize(refs.size());
        for_ranges(refs.size(), threads, [&](size_t b, size_t e) {
            for (size_t i = b; i < e; ++i) {
                const HtSegment& s = base[refs[i].seg()];
                if (ht_seg_flags(s) & HT_SEG_TRIANGLE) {
                    ends[i] = RefEnds{{0.0f, 0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f, -1.0f}};
                    continue;
                }
                const HtPoint& a = geo.points[s.point];
                const HtPoint& b = geo.points[s.point + 1];
                ends[i] = RefEnds{{a.x, a.y, a.z, a.r}, {b.x, b.y, b.z, b.r}};
            }
        });
    }

    // Oriented splits: hair only, a triangle has no direction to bin along.
    Builder builder(refs, opt, ends.empty() ? nullptr : ends.data(),
                    opt.obb_split > 0 && geo.triangle_count == 0);
    const uint32_t root = builder.run();

    // Each output node stems from its own binary node (two records if oriented): that many are
    // allocated but not touched (BulkVector), the flattening fills them in preorder and the rest
    // is cut off.  Not one per reference: with 256-byte records that reservation (64 MB for the
    // strand anchor) made the build ~1.4x slower (host/bvh/NOTES.md "8-wide nodes").
    geo.nodes.clear();
    const size_t records = size_t(builder.used()) * (opt.obb_ratio > 0 ? 2 : 1) + 1;
    if (records >= HT_NODE_ORIENTED) throw std::runtime_error("BVH: too many nodes");
    geo.nodes.resize(records);
    BulkVector<Moments> moments;
    if (opt.obb_ratio > 0) {
        moments.resize(builder.used());
        Flattener::moments_of(builder.nodes(), ends, root, moments, pass_threads(refs.size(), threads));
    }
    Flattener fl{builder.nodes(), geo.nodes.data(), 0, (uint32_t)records, opt, ends, moments, threads};
    Box rb = builder.nodes()[root].box[0];
    rb.grow(builder.nodes()[root].box[1]);
    fl.root_area = std::max(rb.half_area(), 1e-30);
    fl.visit(root, 0, fl.root_area);
    geo.nodes.resize(fl.next);

    geo.segments.clear();
    geo.segments.resize(refs.size());
    for_ranges(refs.size(), threads, [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) geo.segments[i] = base[refs[i].seg()];
    });

    BvhStats& st = geo.stats;
    st.nodes = geo.nodes.size();
    st.oriented = fl.oriented;
    st.oriented_splits = builder.oriented_splits();
    st.leaves = fl.leaves;
    st.max_depth = fl.max_depth;
    st.references = refs.size();
    st.sah_cost = refs.empty() ? 0.0 : fl.sah;
    const double bytes = geo.points.size() * sizeof(HtPoint) +
                         geo.segments.size() * sizeof(HtSegment) +
                         geo.nodes.size() * sizeof(HtBvhNode);
    st.bytes_per_segment = geo.segment_count ? bytes / (double)geo.segment_count : 0.0;
}

}  // namespace

SceneGeometry build_geometry(const Strands& strands, const BvhOptions& opt) {
    static const std::vector<Mesh> kNoMeshes;
    static const std::vector<SurfaceMaterialDesc> kNoMaterials;
    return build_geometry(strands, kNoMeshes, kNoMaterials, opt);
}

SceneGeometry build_geometry(const Strands& strands, const std::vector<Mesh>& meshes,
                             const std::vector<SurfaceMaterialDesc>& surface_materials,
                             const BvhOptions& opt) {
    const auto t0 = std::chrono::steady_clock::now();
    SceneGeometry geo;
    const size_t ns = strands.strand_count();
    size_t triangles = 0;
    for (const Mesh& m : meshes) triangles += m.indices.size() / 3;
    geo.points.reserve(strands.points.size() + 3 * triangles);
    for (size_t i = 0; i < strands.points.size(); ++i) {
        const float r = i < strands.radius.size() ? strands.radius[i] : 0.0f;
        geo.points.push_back(HtPoint{strands.points[i][0], strands.points[i][1], strands.points[i][2], r});
    }
    // Exact: growing by doubling copied the records and faulted in each new block.
    size_t segments = triangles;
    for (size_t s = 0; s < ns; ++s) {
        const uint32_t b = strands.first_point[s], e = strands.first_point[s + 1];
        segments += e > b ? e - b - 1 : 0;
    }
    if (ns > HT_SEG_MAX_STRAND || triangles > HT_SEG_MAX_STRAND)
        throw std::runtime_error("BVH: more than " + std::to_string(HT_SEG_MAX_STRAND) +
                                 " strands or triangles (kernels/types.h HtSegment)");
    // base[global id] (Embree primID: strands back to back)
    BulkVector<HtSegment> base;
    base.reserve(segments);
    geo.triangles.reserve(triangles);
    geo.strand_id_shift.resize(ns);
    for (size_t s = 0; s < ns; ++s) {
        const uint32_t b = strands.first_point[s], e = strands.first_point[s + 1];
        geo.strand_id_shift[s] = b - (uint32_t)base.size();
        for (uint32_t p = b; p + 1 < e; ++p)
            base.push_back(ht_make_segment(p, (uint32_t)s, (p == b ? HT_SEG_FIRST : 0u) | (p + 2 == e ? HT_SEG_LAST : 0u)));
    }
    geo.segment_count = base.size();

    // Triangles after the segments: 3 private vertices each (unindexed, so the traversal reads
    // one contiguous 48-byte run and needs no index buffer).
    for (const Mesh& m : meshes) {
        const SurfaceMaterialDesc mat =
            m.material < surface_materials.size() ? surface_materials[m.material] : SurfaceMaterialDesc{};
        const bool has_normals = m.normals.size() == m.positions.size() && !m.normals.empty();
        // A texture needs coordinates; without them the factor alone is the albedo.
        const bool has_uvs = m.uvs.size() == m.positions.size() && !m.uvs.empty();
        const uint32_t texture = has_uvs && mat.texture >= 0 ? uint32_t(mat.texture) : HT_NO_TEXTURE;
        for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
            base.push_back(ht_make_segment((uint32_t)geo.points.size(), (uint32_t)geo.triangles.size(), HT_SEG_TRIANGLE));
            HtTriangleShading sh{};
            float* normals[3] = {sh.n0, sh.n1, sh.n2};
            for (int v = 0; v < 3; ++v) {
                const uint32_t idx = m.indices[t + v];
                const Vec3f& p = m.positions[idx];
                geo.points.push_back(HtPoint{p[0], p[1], p[2], 0.0f});
                if (has_normals) {
                    for (int k = 0; k < 3; ++k) normals[v][k] = m.normals[idx][k];
                    normals[v][3] = 1.0f;
                }
                if (has_uvs) {
                    sh.uv[2 * v] = m.uvs[idx][0];
                    sh.uv[2 * v + 1] = m.uvs[idx][1];
                }
            }
            for (int k = 0; k < 3; ++k) sh.albedo[k] = mat.albedo[k];
            sh.texture = texture;
            geo.triangles.push_back(sh);
        }
    }
    geo.triangle_count = geo.triangles.size();
    build_bvh_from(base, geo, opt);
    geo.stats.build_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return geo;
}

void rebuild_bvh(SceneGeometry& geo, const BvhOptions& opt) {
    const auto t0 = std::chrono::steady_clock::now();
    BulkVector<HtSegment> base(geo.segment_count + geo.triangle_count);
    for (const HtSegment& s : geo.segments) base[geo.global_id(s)] = s;
    build_bvh_from(base, geo, opt);
    geo.stats.build_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace ht
