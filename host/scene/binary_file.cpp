#include "scene/binary_file.h"

#include <cerrno>
#include <filesystem>
#include <limits>

#include "scene/scene_error.h"

namespace ht {

void require_regular_file(const std::string& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status))
        scene_fail(path, "cannot open: ", ec ? ec.message() : std::string("no such file"));
    if (std::filesystem::is_directory(status)) scene_fail(path, "is a directory, not a scene file");
    if (!std::filesystem::is_regular_file(status)) scene_fail(path, "is not a regular file");
}

BinaryFile::BinaryFile(const std::string& path) : path_(path) {
    require_regular_file(path);
    errno = 0;
    in_.open(path, std::ios::binary);
    if (!in_) scene_fail(path, "cannot open: ", errno ? std::strerror(errno) : "unknown error");
    in_.seekg(0, std::ios::end);
    const std::streamoff end = in_.tellg();
    if (!in_ || end < 0) scene_fail(path, "cannot determine the file size (not a regular file?)");
    size_ = static_cast<uint64_t>(end);
}

void BinaryFile::read(uint64_t offset, void* dst, uint64_t bytes, const char* what) {
    if (offset > size_ || bytes > size_ - offset)
        scene_fail(path_, "file ends inside ", what, " (needs bytes ", offset, "..",
                   offset + bytes, ", the file holds ", size_, ")");
    if (bytes == 0) return;
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(offset));
    // istream::read takes a signed count: read very large arrays in pieces.
    char* out = static_cast<char*>(dst);
    constexpr uint64_t kChunk = uint64_t(1) << 30;
    while (bytes > 0) {
        const uint64_t n = bytes < kChunk ? bytes : kChunk;
        in_.read(out, static_cast<std::streamsize>(n));
        if (static_cast<uint64_t>(in_.gcount()) != n)
            scene_fail(path_, "read error inside ", what, " at byte ", offset,
                       " (was the file changed while loading?)");
        out += n;
        offset += n;
        bytes -= n;
    }
}

}  // namespace ht
