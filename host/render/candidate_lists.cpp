#include "render/candidate_lists.h"

#include <algorithm>
#include <cstring>

namespace ht {

namespace {

// A float's order as an unsigned integer (zeros of either sign alike, as float comparison has
// them): the key of the bands' radix sort.
uint32_t order_bits(float f) {
    uint32_t b;
    std::memcpy(&b, &f, sizeof b);
    if ((b & 0x7FFFFFFFu) == 0) return 0x80000000u;
    return b & 0x80000000u ? ~b : b | 0x80000000u;
}

// Sorts items by key, stably, a byte at a time (a byte all keys share costs no pass); `scratch`
// is the other buffer.  The bands hold ~10^4 spans whose depths share their leading bytes, where
// std::sort's comparisons through the keys were a fifth of the lists' time.
void radix_sort(std::vector<uint64_t>& items, std::vector<uint64_t>& scratch) {
    scratch.resize(items.size());
    uint32_t differ = 0;  // the key bits that are not the same in every item
    for (uint64_t it : items) differ |= uint32_t(it >> 32) ^ uint32_t(items[0] >> 32);
    for (int shift = 32; shift < 64; shift += 8) {
        if (((differ >> (shift - 32)) & 0xFFu) == 0) continue;
        size_t at[257] = {0};
        for (uint64_t it : items) ++at[((it >> shift) & 0xFFu) + 1];
        for (int d = 0; d < 256; ++d) at[d + 1] += at[d];
        for (uint64_t it : items) scratch[at[(it >> shift) & 0xFFu]++] = it;
        items.swap(scratch);
    }
}

// One row's run of one image's pixels in a band, with what its entries hold.
struct Span {
    uint32_t primitive;
    float depth;
    int32_t y, x0, x1;
};

}  // namespace

PixelCandidates pixel_candidates(const ProjectedPrimitives& projected, uint32_t max_per_pixel, uint64_t max_entries) {
    PixelCandidates c;
    if (!projected.bounded) return c;
    const int w = projected.width, h = projected.height;
    const size_t pixels = size_t(w) * size_t(h), n = projected.images.size();
    const BulkVector<PrimitiveImage>& images = projected.images;
    // Rows in bands of kBand.  The images, read in point order, are cut into row spans, each put
    // in its band's spans in that order; each band then sorts its spans nearest first (stably:
    // equal depths stay in point order), so that every pixel's list, filled in that order, comes
    // out sorted.  A band is one thread's work, so the lists do not depend on the thread count.
    // Reading the images in any other order than theirs (a global depth order, or each band's
    // images in depth order) missed the cache on most of them.  Nothing per image or span is
    // copied or grown: fresh memory costs more than the work (core/bulk_vector.h).
    constexpr int kBand = 8;
    const size_t bands = size_t((h + kBand - 1) / kBand), threads = size_t(host_threads());
    // Each band's spans lie in one stretch of `spans`, in which each thread's share of the
    // images has room for as many spans as their rows: region k = b * threads + t, spans
    // [region[k], region[k + 1]), holds band b's spans from thread t's images.
    std::vector<size_t> region(bands * threads + 1, 0);
    in_parallel(n, [&](int t, size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            int r[4];
            if (!images[i].pixel_rect(kCandidateMarginPixels, w, h, r)) continue;
            for (int y = r[2]; y <= r[3]; ++y) ++region[size_t(y / kBand) * threads + size_t(t) + 1];
        }
    });
    for (size_t k = 0; k < bands * threads; ++k) region[k + 1] += region[k];
    BulkVector<Span> spans(region[bands * threads]);
    std::vector<size_t> filled(region.begin(), region.end() - 1);  // each region's next span
    in_parallel(n, [&](int t, size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            const PrimitiveImage& im = images[i];
            int r[4], x0, x1;
            if (!im.pixel_rect(kCandidateMarginPixels, w, h, r)) continue;
            for (int y = r[2]; y <= r[3]; ++y)
                if (im.row_span(y, kCandidateMarginPixels, w, &x0, &x1))
                    spans[filled[size_t(y / kBand) * threads + size_t(t)]++] = Span{im.primitive, im.depth, y, x0, x1};
        }
    });
    // Each band's spans closed up at the start of its stretch, counted and sorted there:
    // spans[band_begin[b] .. band_end[b]).
    std::vector<uint32_t> count(pixels, 0);
    std::vector<size_t> band_begin(bands), band_end(bands);
    struct Scratch {
        std::vector<uint64_t> order, other;
        std::vector<Span> sorted;
    };
    std::vector<Scratch> scratch(threads);
    each_in_parallel(bands, [&](int t, size_t band) {
        Scratch& sc = scratch[size_t(t)];
        const size_t begin = region[band * threads];
        size_t at = begin;
        for (size_t k = band * threads; k < (band + 1) * threads; ++k)
            for (size_t j = region[k]; j < filled[k]; ++j) spans[at++] = spans[j];
        band_begin[band] = begin, band_end[band] = at;
        sc.order.clear();
        for (size_t j = begin; j < at; ++j) {
            const Span& s = spans[j];
            sc.order.push_back(uint64_t(order_bits(s.depth)) << 32 | (j - begin));
            uint32_t* row = &count[size_t(s.y) * size_t(w)];
            for (int x = s.x0; x <= s.x1; ++x) ++row[x];
        }
        radix_sort(sc.order, sc.other);
        sc.sorted.clear();
        for (uint64_t it : sc.order) sc.sorted.push_back(spans[begin + uint32_t(it)]);
        std::copy(sc.sorted.begin(), sc.sorted.end(), spans.begin() + std::ptrdiff_t(begin));
    });
    // A pixel with more than the cap keeps the tree (its list would cost more than a traversal);
    // lists beyond the memory budget halve the cap until they fit.
    std::vector<uint64_t> pixels_with(size_t(max_per_pixel) + 1, 0);  // pixels with k entries, k <= the cap
    for (uint32_t k : count)
        if (k <= max_per_pixel) ++pixels_with[k];
    uint64_t total = 0;
    for (;; max_per_pixel /= 2) {
        if (max_per_pixel < 8) return PixelCandidates{};  // too dense for lists at this budget: the tree for all
        total = 0;
        for (uint32_t k = 1; k <= max_per_pixel; ++k) total += uint64_t(k) * pixels_with[k];
        if (total <= max_entries && total < kCandidatesUseTree) break;
    }
    c.max_per_pixel = max_per_pixel;
    c.start.resize(pixels);
    c.count.resize(pixels);
    total = 0;
    for (size_t p = 0; p < pixels; ++p) {
        c.start[p] = uint32_t(total);
        if (count[p] > max_per_pixel) {
            ++c.tree_pixels;
            c.count[p] = kCandidatesUseTree;
            continue;
        }
        c.count[p] = count[p];
        total += count[p];
    }
    c.primitive.resize(total);
    c.depth.resize(total);
    each_in_parallel(bands, [&](int, size_t band) {
        // back to front, each pixel's count counting down to its list's first slot
        for (size_t j = band_end[band]; j-- > band_begin[band];) {
            const Span& s = spans[j];
            const size_t row = size_t(s.y) * size_t(w);
            for (int x = s.x0; x <= s.x1; ++x) {
                const size_t p = row + size_t(x);
                if (c.count[p] == kCandidatesUseTree) continue;
                const size_t e = size_t(c.start[p]) + --count[p];
                c.primitive[e] = s.primitive;
                c.depth[e] = s.depth;
            }
        }
    });
    for (int i = 0; i < 3; ++i) c.depth_row[i] = float(projected.depth_row[i]);
    c.enabled = true;
    return c;
}

}  // namespace ht
