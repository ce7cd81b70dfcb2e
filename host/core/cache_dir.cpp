#include "core/cache_dir.h"

#include <cstdlib>

namespace ht {

std::string cache_dir() {
    if (const char* d = std::getenv("HAIRTRACE_CACHE_DIR")) return d;
    if (const char* x = std::getenv("XDG_CACHE_HOME")) return std::string(x) + "/hairtrace";
    if (const char* h = std::getenv("HOME")) return std::string(h) + "/.cache/hairtrace";
    return "off";
}

}  // namespace ht
