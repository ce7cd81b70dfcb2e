// Vectors for the large arrays a render builds on the host before its first sample (the
// candidate lists, render/candidate_lists.h): on a virtual machine, touching fresh memory cost
// more than filling it (a page fault per 4 KiB, ~2 us each here: half the lists' time,
// docs/PERFORMANCE.md section 8 "Host work before the first sample").  So:
//  - resize() leaves trivial elements unset: the code that fills them touches each page once,
//    from the thread that fills it, instead of a zero fill on one thread and a second pass;
//  - allocations of 2 MiB or more are aligned to 2 MiB and advised as transparent huge pages
//    (Linux), one fault per 2 MiB where the kernel allows it.
// Anything read before it is written must be assigned first (assign(), or resize(n, value)).
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace ht {

template <typename T>
struct BulkAllocator {
    using value_type = T;
    static constexpr size_t kHugePage = size_t(2) << 20;

    BulkAllocator() noexcept = default;
    template <typename U>
    BulkAllocator(const BulkAllocator<U>&) noexcept {}

    T* allocate(size_t n) {
        if (n > size_t(-1) / sizeof(T)) throw std::bad_array_new_length();
        const size_t bytes = n * sizeof(T);
        if (bytes < kHugePage) {
            if (void* p = std::malloc(bytes ? bytes : 1)) return static_cast<T*>(p);
            throw std::bad_alloc();
        }
        const size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
        void* p = std::aligned_alloc(kHugePage, rounded);
        if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        madvise(p, rounded, MADV_HUGEPAGE);  // advice only: without it, ordinary pages
#endif
        return static_cast<T*>(p);
    }
    void deallocate(T* p, size_t) noexcept { std::free(p); }

    // value-initialisation (resize(n), vector(n)) leaves trivial types unset
    template <typename U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value) {
        ::new (static_cast<void*>(p)) U;
    }
    template <typename U, typename... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }

    template <typename U>
    bool operator==(const BulkAllocator<U>&) const noexcept { return true; }
    template <typename U>
    bool operator!=(const BulkAllocator<U>&) const noexcept { return false; }
};

template <typename T>
using BulkVector = std::vector<T, BulkAllocator<T>>;

}  // namespace ht
