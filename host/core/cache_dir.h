// Where hairtrace keeps what later runs reuse: compiled kernels (host/cl/device.cpp) and the list
// of image formats this build writes (host/io/image_formats.cpp).
#pragma once

#include <string>

namespace ht {

// $HAIRTRACE_CACHE_DIR, else $XDG_CACHE_HOME/hairtrace, else ~/.cache/hairtrace; "off" disables
// the cache.
std::string cache_dir();

}  // namespace ht
