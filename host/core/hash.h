// FNV-1a, 64 bit: the one hash of the host side, for cache keys, file checksums and render
// identities.  It is not a security boundary; it only has to tell different inputs apart.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <type_traits>
#include <vector>

namespace ht {

constexpr uint64_t kFnv1aSeed = 1469598103934665603ull;

// Continues the hash `h` over n bytes (pass the previous result to hash several pieces).
inline uint64_t fnv1a(const void* data, size_t n, uint64_t h = kFnv1aSeed) {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

inline uint64_t fnv1a(const std::string& s, uint64_t h = kFnv1aSeed) { return fnv1a(s.data(), s.size(), h); }

template <typename T, typename Allocator>
uint64_t fnv1a(const std::vector<T, Allocator>& v, uint64_t h = kFnv1aSeed) {
    static_assert(std::is_trivially_copyable_v<T>, "hash only plain bytes");
    return fnv1a(v.data(), v.size() * sizeof(T), h);
}

// "0123456789abcdef": 16 lower-case hex digits, as hashes are shown in files and messages.
inline std::string hex64(uint64_t v) {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", (unsigned long long)v);
    return buf;
}

}  // namespace ht
