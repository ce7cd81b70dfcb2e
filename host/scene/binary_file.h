// Bounds-checked random access reads from a little-endian binary file, for the .hair and .data
// loaders: callers check sizes against size() first, and every read re-checks, so a file that
// shrinks while it is read still gives a SceneError, never garbage.
#pragma once

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>

namespace ht {

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the scene loaders read little-endian files by memcpy and need a little-endian host"
#endif

// Throws SceneError "<path>: ..." unless path names an existing regular file (a directory opens
// fine with ifstream and only fails later with a misleading message).
void require_regular_file(const std::string& path);

class BinaryFile {
public:
    // Opens path for reading; throws SceneError "<path>: cannot open: <reason>".
    explicit BinaryFile(const std::string& path);

    const std::string& path() const { return path_; }
    uint64_t size() const { return size_; }

    // Reads exactly `bytes` bytes at `offset` into dst; throws SceneError naming `what` when the
    // file holds fewer.
    void read(uint64_t offset, void* dst, uint64_t bytes, const char* what);

    template <typename T>
    T read_value(uint64_t offset, const char* what) {
        T value;
        read(offset, &value, sizeof(T), what);
        return value;
    }

private:
    std::string path_;
    std::ifstream in_;
    uint64_t size_ = 0;
};

}  // namespace ht
