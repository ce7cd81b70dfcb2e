// Which image files this build can write: the formats OpenImageIO's plugins can write, by file
// extension, so that a mistyped extension is refused before a render rather than after it.
#pragma once

#include <string>
#include <vector>

namespace ht {

// Lower-case extensions without the dot ("exr", "png", "tif", ...), sorted.  Loads the image
// module (host/core/image_files.h).
const std::vector<std::string>& writable_image_extensions();

// Whether `ext` (as above) is one of them.  Answered from the list a previous run kept in the
// cache folder (host/core/cache_dir.h, under the module file's path, size and time) when that list
// names `ext`, so that `render` checks its outputs without waiting for the module, which loads
// meanwhile in the background (~0.45 s); otherwise from the module's own list, which is then
// kept.  A kept list can only be wrong by naming a format the module lost since (an OpenImageIO
// built without it installed under the same module): that output's write then fails with a
// clear error (exit 3) after the outputs named before it are written.
bool writes_image_extension(const std::string& ext);

}  // namespace ht
