// cl/work_buffer.h: buffers the kernels fill, in host memory on a CPU device from 2 MiB on.
#include <gtest/gtest.h>

#include "cl/work_buffer.h"

#include <cstdint>
#include <vector>

namespace {

TEST(WorkBuffer, HostMemoryOnCpuDevicesFromTwoMiB) {
    ht::ClContext cl;
    const bool cpu = cl.info().type == "CPU";
    const size_t big = 3 * ht::WorkBuffer::kHostBackedFrom + 4096, small = 4096;
    ht::WorkBuffer a(cl, big), b(cl, small);
    EXPECT_EQ(a.host_backed(), cpu);
    EXPECT_FALSE(b.host_backed());

    // Device commands write it and the host reads back what they wrote, before and after a move.
    const uint32_t pattern = 0x9e3779b9u;
    cl.queue().enqueueFillBuffer(a.buffer(), pattern, 0, big);
    cl.queue().enqueueFillBuffer(a.buffer(), 7u, big / 2, 4096);
    std::vector<uint32_t> got(big / 4);
    cl.queue().enqueueReadBuffer(a.buffer(), CL_TRUE, 0, big, got.data());
    EXPECT_EQ(got.front(), pattern);
    EXPECT_EQ(got[big / 8], 7u);
    EXPECT_EQ(got.back(), pattern);

    ht::WorkBuffer c;
    c = std::move(a);
    EXPECT_EQ(c.host_backed(), cpu);
    std::vector<uint32_t> again(big / 4);
    cl.queue().enqueueReadBuffer(c.buffer(), CL_TRUE, 0, big, again.data());
    EXPECT_EQ(again, got);

    // Replacing a buffer by another of its kind (the renderer's allocate()).
    c = ht::WorkBuffer(cl, big);
    cl.queue().enqueueFillBuffer(c.buffer(), 1u, 0, big);
    cl.queue().enqueueReadBuffer(c.buffer(), CL_TRUE, 0, big, again.data());
    EXPECT_EQ(again.back(), 1u);
    cl.queue().finish();
}

}  // namespace
