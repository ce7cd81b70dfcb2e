// A loop over [0, n) cut into one contiguous share per thread, for the host's passes that write
// each element once (the BVH build's, render/primitive_images.h's): a share's pages are faulted in
// by the thread that fills them, and the results do not depend on the thread count.
#pragma once
#include <cstddef>
#include <thread>
#include <vector>

namespace ht {

// body(thread, begin, end) over `threads` (at least 1) contiguous shares of [0, n) in parallel;
// the calling thread takes share 0.
template <typename Body>
void in_parallel(size_t n, int threads, const Body& body) {
    const size_t t = size_t(threads > 1 ? threads : 1);
    std::vector<std::thread> pool;
    for (size_t k = 1; k < t; ++k) pool.emplace_back([&body, n, t, k] { body(int(k), n * k / t, n * (k + 1) / t); });
    body(0, size_t(0), n / t);
    for (std::thread& th : pool) th.join();
}

}  // namespace ht
