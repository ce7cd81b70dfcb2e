#include "render/candidate_lists.h"

#include <algorithm>
#include <thread>

namespace ht {

PixelCandidates pixel_candidates(const ProjectedPrimitives& projected, uint32_t max_per_pixel, uint64_t max_entries) {
    PixelCandidates c;
    if (!projected.bounded) return c;
    const int w = projected.width, h = projected.height;
    const size_t pixels = size_t(w) * size_t(h), n = projected.images.size();
    const std::vector<PrimitiveImage>& images = projected.images;
    std::vector<int> rows(2 * n);
    for (size_t i = 0; i < n; ++i) {
        int r[4];
        if (!images[i].pixel_rect(kCandidateMarginPixels, w, h, r)) r[2] = 0, r[3] = -1;  // no pixel
        rows[2 * i] = r[2], rows[2 * i + 1] = r[3];
    }
    // Rows in bands of kBand, each band's images listed in point order and then sorted nearest
    // first, so that every pixel's list, filled in that order, comes out sorted; the bands are
    // shared out among threads.  One thread fills a band's lists, so they do not depend on the
    // thread count.  No global depth order: sorting all the images and reading them back in it
    // missed the cache on most of them (twice the time).
    constexpr int kBand = 8;
    const int bands = (h + kBand - 1) / kBand;
    std::vector<uint32_t> band_start(size_t(bands) + 1, 0);
    for (size_t i = 0; i < n; ++i)
        if (rows[2 * i] <= rows[2 * i + 1])
            for (int b = rows[2 * i] / kBand; b <= rows[2 * i + 1] / kBand; ++b) ++band_start[size_t(b) + 1];
    for (int b = 0; b < bands; ++b) band_start[size_t(b) + 1] += band_start[size_t(b)];
    std::vector<uint32_t> band_images(band_start[size_t(bands)]);
    {
        std::vector<uint32_t> at(band_start.begin(), band_start.end() - 1);
        for (size_t i = 0; i < n; ++i)
            if (rows[2 * i] <= rows[2 * i + 1])
                for (int b = rows[2 * i] / kBand; b <= rows[2 * i + 1] / kBand; ++b) band_images[at[size_t(b)]++] = uint32_t(i);
    }
    // the bands in contiguous shares, one per thread (render/primitive_images.h in_parallel)
    const auto each_band = [&](const auto& body) {
        in_parallel(size_t(bands), [&](int, size_t first, size_t end) {
            for (size_t band = first; band < end; ++band) body(int(band));
        });
    };
    // each band's images copied out in its order, so that the passes below read them in sequence
    std::vector<PrimitiveImage> band_data(band_images.size());
    std::vector<int> band_rows(2 * band_images.size());
    std::vector<float> keys(n);
    for (size_t i = 0; i < n; ++i) keys[i] = images[i].depth;
    each_band([&](int band) {
        uint32_t* first = band_images.data() + band_start[size_t(band)];
        uint32_t* last = band_images.data() + band_start[size_t(band) + 1];
        std::sort(first, last, [&](uint32_t a, uint32_t b) { return keys[a] < keys[b] || (keys[a] == keys[b] && a < b); });
        for (uint32_t* p = first; p != last; ++p) {
            const size_t at = size_t(p - band_images.data()), i = *p;
            band_data[at] = images[i];
            band_rows[2 * at] = rows[2 * i], band_rows[2 * at + 1] = rows[2 * i + 1];
        }
    });
    const auto in_bands = [&](const auto& body) {
        each_band([&](int band) {
            const int y0 = band * kBand, y1 = std::min(h, y0 + kBand);
            for (uint32_t j = band_start[size_t(band)]; j < band_start[size_t(band) + 1]; ++j) {
                const int a = std::max(band_rows[2 * j], y0), b = std::min(band_rows[2 * j + 1], y1 - 1);
                const PrimitiveImage& im = band_data[j];
                int x0, x1;
                for (int y = a; y <= b; ++y)
                    if (im.row_span(y, kCandidateMarginPixels, w, &x0, &x1)) body(im, y, x0, x1);
            }
        });
    };
    std::vector<uint32_t> count(pixels, 0);
    in_bands([&](const PrimitiveImage&, int y, int x0, int x1) {
        uint32_t* row = &count[size_t(y) * size_t(w)];
        for (int x = x0; x <= x1; ++x) row[x] = row[x] < kCandidatesUseTree - 1 ? row[x] + 1 : row[x];
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
    std::fill(count.begin(), count.end(), 0u);  // now the fill level
    in_bands([&](const PrimitiveImage& im, int y, int x0, int x1) {
        for (int x = x0; x <= x1; ++x) {
            const size_t p = size_t(y) * size_t(w) + size_t(x);
            if (c.count[p] == kCandidatesUseTree) continue;
            const size_t e = size_t(c.start[p]) + count[p]++;
            c.primitive[e] = im.primitive;
            c.depth[e] = im.depth;
        }
    });
    for (int i = 0; i < 3; ++i) c.depth_row[i] = float(projected.depth_row[i]);
    c.enabled = true;
    return c;
}

}  // namespace ht
