#include "io/image_formats.h"

#include "core/cache_dir.h"
#include "core/hash.h"
#include "core/image_files.h"
#include "core/temporary_path.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>

namespace ht {

namespace {

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string item; std::getline(ss, item, sep);)
        if (!item.empty()) out.push_back(item);
    return out;
}

// "extension_list" maps every format to its extensions ("openexr:exr,sxr;png:png;..."),
// "output_format_list" names the formats that can write.  "null" and "term" write no file.
std::vector<std::string> query_writable_extensions() {
    const std::string extensions = image_files::global_attribute("extension_list");
    const std::string writers = image_files::global_attribute("output_format_list");
    const std::vector<std::string> can_write = split(writers, ',');
    std::vector<std::string> out;
    for (const std::string& format : split(extensions, ';')) {
        const auto colon = format.find(':');
        if (colon == std::string::npos) continue;
        const std::string name = format.substr(0, colon);
        if (name == "null" || name == "term") continue;
        if (std::find(can_write.begin(), can_write.end(), name) == can_write.end()) continue;
        for (const std::string& e : split(format.substr(colon + 1), ',')) out.push_back(e);
    }
    std::sort(out.begin(), out.end());
    return out;
}

namespace fs = std::filesystem;

// The kept list's file for the module that is installed now ("" for none: no cache, or no module
// file, as in programs that link the module's code).
fs::path kept_list_path() {
    const std::string dir = cache_dir();
    const std::string stamp = image_files::module_stamp();
    if (dir == "off" || stamp.empty()) return {};
    return fs::path(dir) / ("image_formats_" + hex64(fnv1a(stamp)) + ".txt");
}

// One extension per line, sorted; empty when there is none or it cannot be read.
std::vector<std::string> read_kept_list(const fs::path& path) {
    std::vector<std::string> out;
    if (path.empty()) return out;
    std::ifstream f(path);
    for (std::string line; std::getline(f, line);)
        if (!line.empty()) out.push_back(line);
    if (!std::is_sorted(out.begin(), out.end())) out.clear();
    return out;
}

// Written beside and renamed into place, so a reader sees a whole list or none; a cache that
// cannot be written is only a slower next start.
void keep_list(const fs::path& path, const std::vector<std::string>& extensions) {
    if (path.empty()) return;
    std::error_code ec;
    fs::create_directories(path.parent_path(), ec);
    const fs::path tmp = temporary_beside(path);
    {
        std::ofstream f(tmp);
        for (const std::string& e : extensions) f << e << '\n';
        if (!f) {
            fs::remove(tmp, ec);
            return;
        }
    }
    fs::rename(tmp, path, ec);
    if (ec) fs::remove(tmp, ec);
}

}  // namespace

const std::vector<std::string>& writable_image_extensions() {
    static const std::vector<std::string> extensions = query_writable_extensions();
    return extensions;
}

bool writes_image_extension(const std::string& ext) {
    static std::mutex mutex;
    static bool read = false;
    static fs::path path;
    static std::vector<std::string> kept;
    std::lock_guard<std::mutex> lock(mutex);
    if (!read) {
        path = kept_list_path();
        kept = read_kept_list(path);
        read = true;
    }
    if (std::binary_search(kept.begin(), kept.end(), ext)) return true;
    const std::vector<std::string>& known = writable_image_extensions();
    if (known != kept) {  // written once: kept is the module's list from here on
        keep_list(path, known);
        kept = known;
    }
    return std::binary_search(known.begin(), known.end(), ext);
}

}  // namespace ht
