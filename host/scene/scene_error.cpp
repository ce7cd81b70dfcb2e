#include "scene/scene_error.h"

namespace ht {

std::string one_line(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    bool pending_break = false;
    for (char c : text) {
        if (c == '\n' || c == '\r') {
            pending_break = true;
            continue;
        }
        if (pending_break && !out.empty()) out += "; ";
        pending_break = false;
        out += c;
    }
    return out;
}

void throw_scene_error(const std::string& file, const std::string& problem) {
    throw SceneError(one_line(file + ": " + problem));
}

}  // namespace ht
