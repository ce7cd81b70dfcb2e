// core/bulk_vector.h: a std::vector whose big blocks are 2 MiB aligned (advised as huge pages) and
// whose resize() leaves trivial elements for the writer; everything a vector promises otherwise.
#include <gtest/gtest.h>

#include "core/bulk_vector.h"

#include <cstdint>
#include <numeric>

TEST(BulkVector, BehavesAsAVectorSmallAndLarge) {
    for (const size_t n : {size_t(0), size_t(1), size_t(1000), size_t(3) << 20}) {  // up to 12 MiB of uint32
        ht::BulkVector<uint32_t> v(n);
        std::iota(v.begin(), v.end(), 7u);
        ht::BulkVector<uint32_t> copy = v;
        v.push_back(1);
        ASSERT_EQ(v.size(), n + 1);
        ASSERT_EQ(copy.size(), n);
        for (size_t i = 0; i < n; i += 997) ASSERT_EQ(copy[i], uint32_t(7 + i));
        ht::BulkVector<uint32_t> moved = std::move(v);
        EXPECT_EQ(moved.back(), 1u);
        moved.resize(2 * n + 2, 5u);  // resize with a value fills it
        EXPECT_EQ(moved.back(), 5u);
        moved.assign(10, 9u);
        EXPECT_EQ(std::accumulate(moved.begin(), moved.end(), 0u), 90u);
    }
}

TEST(BulkVector, LargeBlocksAreHugePageAligned) {
    ht::BulkVector<float> big(size_t(1) << 20);  // 4 MiB
    EXPECT_EQ(reinterpret_cast<uintptr_t>(big.data()) % ht::BulkAllocator<float>::kHugePage, 0u);
    big[big.size() - 1] = 1.5f;
    EXPECT_EQ(big.back(), 1.5f);
}
