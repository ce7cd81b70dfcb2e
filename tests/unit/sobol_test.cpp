// Host (double) checks of the Owen-scrambled Sobol' sampler (kernels/sobol.h) and of the
// dimension layout that feeds it (kernels/rng.h): the very lines the kernels run.
#include <gtest/gtest.h>

#include "kernels/rng.h"

#include <cmath>
#include <utility>
#include <vector>

namespace {

// The pairs of slots that rng.h promises to stratify jointly.
const std::pair<uint, uint> kPairs[] = {
    {HT_DIM_PIXEL_X, HT_DIM_PIXEL_Y},
    {HT_DIM_LIGHT_U, HT_DIM_LIGHT_V},
    {HT_DIM_BSDF_0 + 1u, HT_DIM_BSDF_0 + 2u},
    {HT_DIM_BSDF_0, HT_DIM_BSDF_0 + 3u},
};
const uint kAllSlots[] = {HT_DIM_PIXEL_X, HT_DIM_PIXEL_Y, HT_DIM_LIGHT_PICK, HT_DIM_LIGHT_U,
                          HT_DIM_LIGHT_V, HT_DIM_BSDF_0, HT_DIM_BSDF_0 + 1u, HT_DIM_BSDF_0 + 2u,
                          HT_DIM_BSDF_0 + 3u, HT_DIM_RR};

// Every elementary interval of area 2^-m (2^a by 2^(m-a) cells, each a) holds exactly one of
// the 2^m points: a (0,m,2)-net.
bool is_02_net(const std::vector<double>& x, const std::vector<double>& y, int m) {
    const size_t n = size_t(1) << m;
    if (x.size() != n || y.size() != n) return false;
    for (int a = 0; a <= m; ++a) {
        const double cx = double(1u << a), cy = double(1u << (m - a));
        std::vector<int> count(n, 0);
        for (size_t i = 0; i < n; ++i) {
            const size_t ix = size_t(std::floor(x[i] * cx)), iy = size_t(std::floor(y[i] * cy));
            if (++count[iy * (size_t(1) << a) + ix] != 1) return false;
        }
    }
    return true;
}

TEST(Sobol, UnscrambledPointsAreJoeKuos) {
    // The classic first points of the 3-D Sobol' sequence (Gray-code order: point n is index n ^ (n >> 1)).
    const double expected[8][3] = {{0, 0, 0},           {0.5, 0.5, 0.5},     {0.75, 0.25, 0.25},
                                   {0.25, 0.75, 0.75},  {0.375, 0.375, 0.625}, {0.875, 0.875, 0.125},
                                   {0.625, 0.125, 0.875}, {0.125, 0.625, 0.375}};
    for (uint n = 0; n < 8; ++n)
        for (uint d = 0; d < 3; ++d)
            EXPECT_EQ(ht_sobol_bits(n ^ (n >> 1), d) * 0x1p-32, expected[n][d]) << "n " << n << " dim " << d;
}

TEST(Sobol, UnscrambledDimensionsAreEach1DStratified) {
    for (uint d = 0; d < 4; ++d)
        for (int m = 0; m <= 12; ++m) {
            std::vector<int> count(size_t(1) << m, 0);
            // the top m bits (none for m = 0: a shift by 32 would be undefined)
            for (uint i = 0; i < (1u << m); ++i) ++count[m == 0 ? 0u : ht_sobol_bits(i, d) >> (32 - m)];
            for (int c : count) ASSERT_EQ(c, 1) << "dim " << d << " m " << m;
        }
}

TEST(Sobol, OwenScrambleIsANestedPermutation) {
    // Nested: the top k bits of the output depend only on the top k bits of the input, and the
    // map is one to one (checked on the top 12 bits, every seed alike).
    for (uint seed : {0u, 1u, 0xdeadbeefu, 0x12345678u}) {
        std::vector<int> seen(4096, 0);
        for (uint top = 0; top < 4096; ++top) {
            const uint out = ht_owen_scramble(top << 20, seed);
            ++seen[out >> 20];
            EXPECT_EQ(ht_owen_scramble((top << 20) | 0xfffffu, seed) >> 20, out >> 20);
        }
        for (int s : seen) ASSERT_EQ(s, 1);
    }
}

TEST(Sobol, ShuffleKeepsEveryPowerOfTwoPrefixAndBlock) {
    // Samples [b 2^m, (b + 1) 2^m) map to indices of one aligned block of 2^m, each once; block 0
    // onto [0, 2^m) itself (so the Sobol' loop stays short).
    for (uint seed : {0u, 7u, 0x9e3779b9u})
        for (int m = 0; m <= 12; ++m)
            for (uint block : {0u, 5u}) {
                const uint n = 1u << m;
                std::vector<int> seen(n, 0);
                const uint first = ht_sobol_shuffle(block * n, seed) >> m;
                for (uint i = 0; i < n; ++i) {
                    const uint index = ht_sobol_shuffle(block * n + i, seed);
                    ASSERT_EQ(index >> m, block == 0u ? 0u : first) << "seed " << seed << " m " << m;
                    ++seen[index & (n - 1u)];
                }
                for (int c : seen) ASSERT_EQ(c, 1);
            }
}

TEST(Sobol, JointlyUsedPairsAre02NetsAfterScrambling) {
    // For every power of two up to 2^10, in the first block and in a later one (chunks start at
    // multiples of 16), at several seeds, pixels and bounces.
    for (uint seed : {1u, 99u})
        for (uint pixel : {0u, 1u, 12345u})
            for (uint bounce : {0u, 3u})
                for (const auto& pr : kPairs)
                    for (int m = 0; m <= 10; ++m)
                        for (uint block : {0u, 3u}) {
                            const uint n = 1u << m;
                            std::vector<double> x, y;
                            for (uint i = 0; i < n; ++i) {
                                x.push_back(ht_sobol_sample(seed, pixel, block * n + i, bounce, pr.first));
                                y.push_back(ht_sobol_sample(seed, pixel, block * n + i, bounce, pr.second));
                            }
                            ASSERT_TRUE(is_02_net(x, y, m))
                                << "slots " << pr.first << "," << pr.second << " m " << m << " block " << block
                                << " pixel " << pixel << " bounce " << bounce;
                        }
}

TEST(Sobol, EverySlotIs1DStratified) {
    for (uint slot : kAllSlots)
        for (int m = 0; m <= 10; ++m) {
            std::vector<int> count(size_t(1) << m, 0);
            for (uint i = 0; i < (1u << m); ++i)
                ++count[size_t(std::floor(ht_sobol_sample(7u, 42u, i, 1u, slot) * double(1u << m)))];
            for (int c : count) ASSERT_EQ(c, 1) << "slot " << slot << " m " << m;
        }
}

TEST(Sobol, ValuesAreInTheUnitIntervalAndDeterministic) {
    for (uint pixel = 0; pixel < 64; ++pixel)
        for (uint sample = 0; sample < 64; ++sample)
            for (uint slot : kAllSlots) {
                const double u = ht_sobol_sample(3u, pixel * 7919u, sample, pixel % 6u, slot);
                ASSERT_GE(u, 0.0);
                ASSERT_LT(u, 1.0);
                ASSERT_EQ(u, ht_sobol_sample(3u, pixel * 7919u, sample, pixel % 6u, slot));
                // exact in float: the kernels see the same number
                ASSERT_EQ(double(float(u)), u);
            }
}

double mean_of(const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return s / double(v.size());
}

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
    const double ma = mean_of(a), mb = mean_of(b);
    double sab = 0, saa = 0, sbb = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        sab += (a[i] - ma) * (b[i] - mb);
        saa += (a[i] - ma) * (a[i] - ma);
        sbb += (b[i] - mb) * (b[i] - mb);
    }
    return sab / std::sqrt(saa * sbb);
}

TEST(Sobol, DimensionsOfOnePixelAreDecorrelated) {
    // 1,000 samples (not a power of two) of every slot of bounces 0..2 in one pixel: uniform
    // moments, no two dimensions alike or correlated.
    const uint n = 1000;
    std::vector<std::vector<double>> dims;
    for (uint bounce = 0; bounce < 3; ++bounce)
        for (uint slot : kAllSlots) {
            std::vector<double> v;
            for (uint i = 0; i < n; ++i) v.push_back(ht_sobol_sample(5u, 777u, i, bounce, slot));
            const double m = mean_of(v);
            double var = 0;
            for (double x : v) var += (x - m) * (x - m);
            var /= n;
            EXPECT_NEAR(m, 0.5, 0.01) << "bounce " << bounce << " slot " << slot;
            EXPECT_NEAR(var, 1.0 / 12.0, 0.004) << "bounce " << bounce << " slot " << slot;
            dims.push_back(v);
        }
    // Groups are paired by nested (Owen) shuffles of the index, not by uniformly random
    // permutations: their correlations spread ~1.2x wider than independent numbers' 1/sqrt(n).
    double sum_sq = 0;
    int pairs = 0;
    for (size_t a = 0; a < dims.size(); ++a)
        for (size_t b = a + 1; b < dims.size(); ++b) {
            EXPECT_NE(dims[a], dims[b]) << a << " " << b;
            const double c = correlation(dims[a], dims[b]);
            EXPECT_LT(std::fabs(c), 0.2) << a << " " << b;
            sum_sq += c * c;
            ++pairs;
        }
    EXPECT_LT(std::sqrt(sum_sq / pairs), 1.5 / std::sqrt(double(n)));
}

TEST(Sobol, PixelsAreDecorrelated) {
    // The same slot and sample across 4,096 neighbouring pixels is uniform, and a pixel's
    // sequence is unrelated to its neighbour's (each pixel shuffles its own way).
    for (uint slot : kAllSlots) {
        std::vector<double> across;
        for (uint pixel = 0; pixel < 4096; ++pixel) across.push_back(ht_sobol_sample(1u, pixel, 5u, 0u, slot));
        EXPECT_NEAR(mean_of(across), 0.5, 0.015) << "slot " << slot;
        std::vector<double> a, b;
        for (uint i = 0; i < 256; ++i) {
            a.push_back(ht_sobol_sample(1u, 100u, i, 0u, slot));
            b.push_back(ht_sobol_sample(1u, 101u, i, 0u, slot));
        }
        EXPECT_LT(std::fabs(correlation(a, b)), 0.2) << "slot " << slot;
    }
}

TEST(Sobol, PointsAreThoseOfTheDirectionNumberTable) {
    // The kernels make direction numbers by their recurrence, bit-reversed, on the fly; here they
    // come from the textbook construction instead (Joe & Kuo's m_k, v_k = m_k 2^(32-k), the
    // recurrence written out over a table) and point n is the xor of v_k over n's bits -- for every
    // index of the first 2^18 and the highest 4,096 of every dimension.
    const uint degree[4] = {0, 1, 2, 3}, coeffs[4] = {0, 0, 1, 1};  // a_1..a_{s-1} as bits, x^3+x+1: a = (0, 1)
    const uint m_init[4][3] = {{1, 0, 0}, {1, 0, 0}, {1, 3, 0}, {1, 3, 1}};
    for (uint d = 0; d < 4; ++d) {
        uint v[33];
        for (uint k = 1; k <= 32; ++k) {
            if (d == 0) {
                v[k] = 1u << (32 - k);
            } else if (k <= degree[d]) {
                v[k] = m_init[d][k - 1] << (32 - k);
            } else {
                const uint s = degree[d];
                uint x = v[k - s] ^ (v[k - s] >> s);
                for (uint j = 1; j < s; ++j)
                    if ((coeffs[d] >> (s - 1 - j)) & 1u) x ^= v[k - j];
                v[k] = x;
            }
        }
        auto point = [&](uint n) {
            uint x = 0;
            for (uint k = 1; n != 0; ++k, n >>= 1)
                if (n & 1u) x ^= v[k];
            return x;
        };
        for (uint i = 0; i < (1u << 18); ++i) ASSERT_EQ(ht_sobol_bits(i, d), point(i)) << "dim " << d << " i " << i;
        for (uint i = 0xffffffffu; i > 0xffffffffu - 4096u; --i)
            ASSERT_EQ(ht_sobol_bits(i, d), point(i)) << "dim " << d << " i " << i;
    }
}

TEST(Sobol, PairsDrawnTogetherAreTheSameNumbers) {
    // ht_sample2 (both samplers) and the Sobol' pair share a group's seed and shuffle: each pair of
    // the layout must give exactly what two single draws give.
    for (const auto& pr : kPairs)
        for (uint bounce = 0; bounce < 6; ++bounce)
            for (uint pixel = 0; pixel < 64; ++pixel)
                for (uint sample = 0; sample < 300; sample += 7) {
                    const uint seed = 11u + pixel * 131u;
                    double a = -1, b = -1;
                    ht_sobol_sample2(seed, pixel * 7919u, sample, bounce, pr.first, &a, &b);
                    ASSERT_EQ(a, ht_sobol_sample(seed, pixel * 7919u, sample, bounce, pr.first));
                    ASSERT_EQ(b, ht_sobol_sample(seed, pixel * 7919u, sample, bounce, pr.second));
                    ht_sample2(seed, pixel, sample, bounce, pr.first, pr.second, &a, &b);
                    ASSERT_EQ(a, ht_sample(seed, pixel, sample, bounce, pr.first));
                    ASSERT_EQ(b, ht_sample(seed, pixel, sample, bounce, pr.second));
                }
}

TEST(Sobol, SeedsGiveOtherSequences) {
    int same = 0;
    for (uint i = 0; i < 256; ++i)
        same += ht_sobol_sample(1u, 9u, i, 0u, HT_DIM_PIXEL_X) == ht_sobol_sample(2u, 9u, i, 0u, HT_DIM_PIXEL_X);
    EXPECT_LT(same, 8);
}

TEST(Sobol, HostDefaultIsTheIndependentSampler) {
    // Without HT_SAMPLER_SOBOL (the renderer defines it for --sampler sobol) ht_sample is the
    // counter-based hash, dimension bounce * HT_DIMS_PER_BOUNCE + slot.
    for (uint slot : kAllSlots)
        EXPECT_EQ(ht_sample(4u, 10u, 3u, 2u, slot), ht_uniform(4u, 10u, 3u, ht_dim(2u, slot)));
}

}  // namespace
