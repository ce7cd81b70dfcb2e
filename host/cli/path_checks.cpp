#include "cli/path_checks.h"

#include "io/image_formats.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <unistd.h>

namespace ht {

namespace {
namespace fs = std::filesystem;

std::string lower_extension(const std::string& path) {
    std::string e = fs::path(path).extension().string();
    if (!e.empty()) e.erase(0, 1);
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

std::string image_format_hint() {
    const auto& all = writable_image_extensions();
    return "exr, hdr, tif (linear float), png, jpg (8-bit sRGB) or another of the " + std::to_string(all.size()) +
           " extensions OpenImageIO writes here";
}

void check_image_extension(const std::string& what, const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext.empty())
        throw UsageError(what + " " + path + ": no file extension to choose the image format from (" +
                         image_format_hint() + ")");
    if (!writes_image_extension(ext))
        throw UsageError(what + " " + path + ": '." + ext + "' is not an image format this build can write (" +
                         image_format_hint() + ")");
}

// Creating a file is the only test that answers for every reason a write can fail (permissions,
// read-only mounts, ACLs, pseudo file systems); access(2) would not.
void check_writable_folder(const std::string& what, const std::string& path) {
    if (fs::is_directory(path)) throw UsageError(what + " " + path + ": is a folder, not a file name");
    fs::path folder = fs::path(path).parent_path();
    if (folder.empty()) folder = ".";
    std::error_code ec;
    if (!fs::exists(folder, ec))
        throw UsageError(what + " " + path + ": the folder " + folder.string() + " does not exist");
    if (!fs::is_directory(folder, ec))
        throw UsageError(what + " " + path + ": " + folder.string() + " is not a folder");
    std::string probe = (folder / ".hairtrace-write-test-XXXXXX").string();
    const int fd = ::mkstemp(probe.data());
    if (fd < 0)
        throw UsageError(what + " " + path + ": cannot write in the folder " + folder.string() + " (" +
                         std::strerror(errno) + ")");
    ::close(fd);
    ::unlink(probe.c_str());
}

}  // namespace

void check_path(const std::string& what, const std::string& path, PathKind kind) {
    if (path.empty()) throw UsageError(what + ": needs a file name");
    switch (kind) {
    case PathKind::Input:
        if (!fs::exists(path)) throw UsageError(what + " " + path + ": the file does not exist");
        if (fs::is_directory(path)) throw UsageError(what + " " + path + ": is a folder, not a file");
        return;
    case PathKind::InputFolder:
        if (!fs::is_directory(path)) throw UsageError(what + " " + path + ": no such folder");
        return;
    case PathKind::Image:
        check_image_extension(what, path);
        break;
    case PathKind::Csv:
        if (lower_extension(path) != "csv")
            throw UsageError(what + " " + path + ": a CSV file name must end in .csv");
        break;
    case PathKind::AnyOutput:
        break;
    }
    check_writable_folder(what, path);
}

}  // namespace ht
