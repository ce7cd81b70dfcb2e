#include "io/image_formats.h"

#include "core/image_files.h"

#include <algorithm>
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

}  // namespace

const std::vector<std::string>& writable_image_extensions() {
    static const std::vector<std::string> extensions = query_writable_extensions();
    return extensions;
}

}  // namespace ht
