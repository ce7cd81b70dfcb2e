// Files are written beside their target under a name of this process's and renamed into place, so
// a reader (or a previous image) never sees a half-written file.
#pragma once

#include <filesystem>
#include <string>

#include <unistd.h>

namespace ht {

// ".tmp.<pid>.<name>" in the target's folder: hidden, and unique among concurrent writers.
inline std::filesystem::path temporary_beside(const std::filesystem::path& target) {
    return target.parent_path() / (".tmp." + std::to_string(::getpid()) + "." + target.filename().string());
}

}  // namespace ht
