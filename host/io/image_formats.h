// Which image files this build can write: the formats OpenImageIO's plugins can write, by file
// extension, so that a mistyped extension is refused before a render rather than after it.
#pragma once

#include <string>
#include <vector>

namespace ht {

// Lower-case extensions without the dot ("exr", "png", "tif", ...), sorted.
const std::vector<std::string>& writable_image_extensions();

}  // namespace ht
