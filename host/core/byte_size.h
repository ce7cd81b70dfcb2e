// Byte sizes as people write and read them: --max-memory 512M, HAIRTRACE_MAX_ALLOC=64K, and
// "1.5 GiB" in messages.  Binary units (K = 1024).
#pragma once

#include <cstdint>
#include <string>

namespace ht {

// "1.5 GiB", "12.0 MiB", "512 bytes"
std::string format_bytes(uint64_t bytes);

// "512M", "8G", "64KiB", "1073741824" -> bytes; throws std::invalid_argument.
uint64_t parse_bytes(const std::string& text);

}  // namespace ht
