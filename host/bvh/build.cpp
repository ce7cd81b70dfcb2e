// Binned-SAH BVH over capsule segments, built with a few std::threads and flattened depth-first
// into HtBvhNode ("SoA in node": each node holds both children's boxes).
#include "bvh/bvh.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <thread>

#include "kernels/geometry/bvh_traverse.h"

// The traversal pushes at most one entry per level, so the depth cap keeps the stack safe.
// Flattener::visit collapses two binary levels per 4-wide node, so a 4-wide node on the path
// to a leaf sits at binary depth >= 2 x its own; each pushes at most 3 entries.
static_assert(3 * (ht::kMaxBvhDepth / 2 + 1) < HT_STACK_SIZE, "BVH depth cap must fit the kernel stack");

namespace ht {
namespace {

struct Box {
    float lo[3] = {INFINITY, INFINITY, INFINITY};
    float hi[3] = {-INFINITY, -INFINITY, -INFINITY};

    void grow(const Box& b) {
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], b.lo[k]);
            hi[k] = std::max(hi[k], b.hi[k]);
        }
    }
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

// One BVH reference: a (piece of a) segment's box and the index of the segment in global order.
struct Ref {
    Box box;
    uint32_t seg;
};

// Intermediate node while building: both child slots as the final layout has them, children
// referring to intermediate node indices.
struct BNode {
    Box box[2];
    uint32_t child[2] = {0, 0};
    uint32_t count[2] = {0, 0};
};

struct Slot {
    Box box;
    uint32_t child = 0, count = 0;  // count > 0: leaf [child, child + count) of the refs
};

// Binning scratch.  Reused per thread (thread_local in Builder::build) and reset for the bins
// in use only: initialising all kMax boxes of 3 axes for each of ~N/1.3 nodes cost about a
// quarter of the build.
struct Bins {
    static constexpr int kMax = 64;
    Box box[3][kMax];
    uint32_t n[3][kMax];
    Box right_box[kMax];  // sweep scratch
    uint32_t right_n[kMax];
    void reset(int bins) {
        for (int a = 0; a < 3; ++a)
            for (int i = 0; i < bins; ++i) {
                box[a][i] = Box();
                n[a][i] = 0;
            }
    }
    void merge(const Bins& o, int bins) {
        for (int a = 0; a < 3; ++a)
            for (int i = 0; i < bins; ++i) {
                box[a][i].grow(o.box[a][i]);
                n[a][i] += o.n[a][i];
            }
    }
};

class Builder {
public:
    Builder(std::vector<Ref>& refs, const BvhOptions& opt)
        : refs_(refs), opt_(opt), bins_(std::clamp(opt.bins, 4, Bins::kMax)) {
        unsigned t = opt.threads ? opt.threads : std::max(1u, std::thread::hardware_concurrency());
        tokens_ = (int)t - 1;
        // A binary tree over n references has at most n - 1 inner nodes (+1 for a leaf root).
        nodes_.resize(std::max<size_t>(refs.size(), 1));
    }

    // Returns the intermediate root node index.
    uint32_t run() {
        if (refs_.empty()) return alloc();  // both slots empty
        Box bounds, cbounds;
        bounds_of(0, (uint32_t)refs_.size(), bounds, cbounds);
        Slot top = build(0, (uint32_t)refs_.size(), bounds, cbounds, 1);
        if (top.count == 0) return top.child;
        uint32_t root = alloc();  // the whole scene is one leaf: root with one used slot
        nodes_[root].box[0] = top.box;
        nodes_[root].child[0] = top.child;
        nodes_[root].count[0] = top.count;
        return root;
    }

    std::vector<BNode> nodes_;

private:
    uint32_t alloc() { return used_.fetch_add(1); }

    void bounds_of(uint32_t b, uint32_t e, Box& bounds, Box& cbounds) const {
        for (uint32_t i = b; i < e; ++i) {
            bounds.grow(refs_[i].box);
            float c[3] = {refs_[i].box.center(0), refs_[i].box.center(1), refs_[i].box.center(2)};
            cbounds.grow_point(c, 0.0f);
        }
    }

    void bin_range(uint32_t b, uint32_t e, const Box& cb, const float* scale, int nb,
                   Bins& out) const {
        for (uint32_t i = b; i < e; ++i) {
            const Box& bx = refs_[i].box;
            for (int a = 0; a < 3; ++a) {
                int k = (int)((bx.center(a) - cb.lo[a]) * scale[a]);
                k = std::clamp(k, 0, nb - 1);
                out.box[a][k].grow(bx);
                out.n[a][k]++;
            }
        }
    }

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

    Slot build(uint32_t b, uint32_t e, const Box& bounds, const Box& cbounds, int depth) {
        const uint32_t n = e - b;
        const double leaf_cost = opt_.c_isect * (double)n;
        if (n == 1 || depth >= kMaxBvhDepth) return leaf(b, e, bounds);

        // ---- binning (two threads for the big top-level ranges)
        // Small nodes get fewer bins: the SAH sweep is O(bins) per axis and dominated the
        // build for the ~N/2 nodes near the leaves, where n bins resolve as much as 16.
        const int nb = std::min(bins_, std::max(4, (int)n));
        float scale[3];
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
        double best_cost = INFINITY;
        int best_axis = -1, best_split = 0;
        Box best_l, best_r;
        for (int a = 0; a < 3; ++a) {
            if (scale[a] == 0.0f) continue;
            Box* right_box = bins.right_box;
            uint32_t* right_n = bins.right_n;
            Box acc;
            uint32_t cnt = 0;
            for (int i = nb - 1; i > 0; --i) {
                acc.grow(bins.box[a][i]);
                cnt += bins.n[a][i];
                right_box[i] = acc;
                right_n[i] = cnt;
            }
            Box left;
            uint32_t ln = 0;
            for (int i = 1; i < nb; ++i) {
                left.grow(bins.box[a][i - 1]);
                ln += bins.n[a][i - 1];
                if (ln == 0 || right_n[i] == 0) continue;
                const double cost = opt_.c_trav + opt_.c_isect * inv_area *
                                                      (left.half_area() * ln +
                                                       right_box[i].half_area() * right_n[i]);
                if (cost < best_cost) {
                    best_cost = cost;
                    best_axis = a;
                    best_split = i;
                    best_l = left;
                    best_r = right_box[i];
                }
            }
        }

        if (n <= (uint32_t)opt_.max_leaf && leaf_cost <= best_cost) return leaf(b, e, bounds);

        uint32_t mid;
        if (best_axis >= 0) {
            const int a = best_axis;
            const float lo = cbounds.lo[a], sc = scale[a];
            auto it = std::partition(refs_.begin() + b, refs_.begin() + e, [&](const Ref& r) {
                int k = std::clamp((int)((r.box.center(a) - lo) * sc), 0, nb - 1);
                return k < best_split;
            });
            mid = (uint32_t)(it - refs_.begin());
        } else {
            // All centroids coincide (duplicated or split pieces): halve the range.
            mid = b + n / 2;
            best_l = Box();
            best_r = Box();
        }
        Box cl, cr;
        if (best_axis < 0) {
            bounds_of(b, mid, best_l, cl);
            bounds_of(mid, e, best_r, cr);
        } else {
            cl = Box();
            cr = Box();
            // Centroid bounds of the children (one pass each; the boxes came from the bins).
            for (uint32_t i = b; i < mid; ++i) {
                float c[3] = {refs_[i].box.center(0), refs_[i].box.center(1), refs_[i].box.center(2)};
                cl.grow_point(c, 0.0f);
            }
            for (uint32_t i = mid; i < e; ++i) {
                float c[3] = {refs_[i].box.center(0), refs_[i].box.center(1), refs_[i].box.center(2)};
                cr.grow_point(c, 0.0f);
            }
        }

        const uint32_t id = alloc();
        Slot left, right;
        if (n >= 4096 && take_token()) {
            std::thread th([&] { left = build(b, mid, best_l, cl, depth + 1); });
            right = build(mid, e, best_r, cr, depth + 1);
            th.join();
            give_token();
        } else {
            left = build(b, mid, best_l, cl, depth + 1);
            right = build(mid, e, best_r, cr, depth + 1);
        }
        BNode& node = nodes_[id];
        node.box[0] = left.box;
        node.box[1] = right.box;
        node.child[0] = left.child;
        node.child[1] = right.child;
        node.count[0] = left.count;
        node.count[1] = right.count;
        Slot s;
        s.box = bounds;
        s.child = id;
        s.count = 0;
        return s;
    }

    std::vector<Ref>& refs_;
    BvhOptions opt_;
    int bins_;
    std::atomic<int> tokens_{0};
    std::atomic<uint32_t> used_{0};
};

// Binary build tree -> 4-wide nodes, depth-first preorder.  A 4-wide node takes the children of
// both of its binary node's children (a leaf child stays a leaf slot), i.e. always two binary
// levels: the stack bound above relies on it.  (Opening the largest-area child first, as Embree's
// and Cycles' collapses do, would pack more nodes full but could descend one level only.)
struct Flattener {
    const std::vector<BNode>& in;
    std::vector<HtBvhNode>& out;
    const BvhOptions& opt;
    double root_area = 1;
    double sah = 0;
    size_t leaves = 0, max_depth = 0;

    // Returns the output index of intermediate node `id`.
    uint32_t visit(uint32_t id, size_t depth) {
        const uint32_t me = (uint32_t)out.size();
        out.emplace_back();
        max_depth = std::max(max_depth, depth);
        const BNode& bn = in[id];
        Slot slot[4];
        int m = 0;
        Box all;
        for (int s = 0; s < 2; ++s) {
            if (bn.count[s] == 0 && bn.child[s] == 0) continue;  // empty (0- or 1-segment scene)
            all.grow(bn.box[s]);
            if (bn.count[s] > 0) {
                slot[m++] = Slot{bn.box[s], bn.child[s], bn.count[s]};
                continue;
            }
            const BNode& g = in[bn.child[s]];
            for (int t = 0; t < 2; ++t)
                if (g.count[t] > 0 || g.child[t] != 0) slot[m++] = Slot{g.box[t], g.child[t], g.count[t]};
        }
        sah += opt.c_trav * all.half_area() / root_area;
        uint32_t child[4] = {0, 0, 0, 0};
        for (int k = 0; k < m; ++k) {
            if (slot[k].count > 0) {
                child[k] = slot[k].child;
                ++leaves;
                max_depth = std::max(max_depth, depth + 1);
                sah += opt.c_isect * slot[k].count * slot[k].box.half_area() / root_area;
            } else {
                child[k] = visit(slot[k].child, depth + 1);
            }
        }
        HtBvhNode& n = out[me];
        for (int k = 0; k < 4; ++k) {
            const bool used = k < m;
            for (int a = 0; a < 3; ++a) {
                float* axis = a == 0 ? n.x : a == 1 ? n.y : n.z;
                axis[k] = used ? slot[k].box.lo[a] : 0.0f;
                axis[k + 4] = used ? slot[k].box.hi[a] : 0.0f;
            }
            n.child[k] = child[k];
            n.count[k] = used ? slot[k].count : 0u;
        }
        return me;
    }
};

// Box of the capsule piece between parameters [a, b] of the segment, split while it pays.
void add_refs(std::vector<Ref>& refs, uint32_t seg, const float* p0, const float* p1, float r,
              float a, float b, int depth, const BvhOptions& opt) {
    float pa[3], pb[3];
    for (int k = 0; k < 3; ++k) {
        pa[k] = p0[k] + (p1[k] - p0[k]) * a;
        pb[k] = p0[k] + (p1[k] - p0[k]) * b;
    }
    Ref ref;
    ref.seg = seg;
    ref.box.grow_point(pa, r);
    ref.box.grow_point(pb, r);
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

void build_bvh_from(const std::vector<HtSegment>& base, SceneGeometry& geo, const BvhOptions& opt) {
    std::vector<Ref> refs;
    refs.reserve(base.size());
    for (uint32_t i = 0; i < base.size(); ++i) {
        if (base[i].flags & HT_SEG_TRIANGLE) {
            // Triangles are never split: their boxes are tight already for mesh-like shapes.
            Ref ref;
            ref.seg = i;
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

    Builder builder(refs, opt);
    const uint32_t root = builder.run();

    geo.nodes.clear();
    geo.nodes.reserve(std::max<size_t>(refs.size(), 1));
    Flattener fl{builder.nodes_, geo.nodes, opt};
    Box rb = builder.nodes_[root].box[0];
    rb.grow(builder.nodes_[root].box[1]);
    fl.root_area = std::max(rb.half_area(), 1e-30);
    fl.visit(root, 0);

    geo.segments.resize(refs.size());
    for (size_t i = 0; i < refs.size(); ++i) geo.segments[i] = base[refs[i].seg];

    BvhStats& st = geo.stats;
    st.nodes = geo.nodes.size();
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
    geo.points.resize(strands.points.size());
    for (size_t i = 0; i < strands.points.size(); ++i) {
        const float r = i < strands.radius.size() ? strands.radius[i] : 0.0f;
        geo.points[i] = HtPoint{strands.points[i][0], strands.points[i][1], strands.points[i][2], r};
    }
    std::vector<HtSegment> base;
    const size_t ns = strands.strand_count();
    for (size_t s = 0; s < ns; ++s) {
        const uint32_t b = strands.first_point[s], e = strands.first_point[s + 1];
        for (uint32_t p = b; p + 1 < e; ++p) {
            HtSegment seg;
            seg.point = p;
            seg.segment = (uint32_t)base.size();  // Embree primID: strands back to back
            seg.strand = (uint32_t)s;
            seg.flags = p == b ? HT_SEG_FIRST : 0u;
            base.push_back(seg);
        }
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
            HtSegment seg;
            seg.point = (uint32_t)geo.points.size();
            seg.segment = (uint32_t)base.size();
            seg.strand = (uint32_t)geo.triangles.size();
            seg.flags = HT_SEG_TRIANGLE;
            base.push_back(seg);
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
    std::vector<HtSegment> base(geo.segment_count + geo.triangle_count);
    for (const HtSegment& s : geo.segments) base[s.segment] = s;
    build_bvh_from(base, geo, opt);
    geo.stats.build_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace ht
