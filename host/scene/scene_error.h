// Building SceneError messages: always one line, "<file>: <problem>".
#pragma once

#include <sstream>
#include <string>
#include <utility>

#include "scene/scene.h"

namespace ht {

// Concatenates anything streamable into a string.
template <typename... Args>
std::string str_cat(Args&&... args) {
    std::ostringstream out;
    (out << ... << std::forward<Args>(args));
    return out.str();
}

// Line breaks inside a problem (e.g. a parser's multi-line report) become "; " so that every
// SceneError stays a single line.
std::string one_line(const std::string& text);

[[noreturn]] void throw_scene_error(const std::string& file, const std::string& problem);

template <typename... Args>
[[noreturn]] void scene_fail(const std::string& file, Args&&... problem) {
    throw_scene_error(file, str_cat(std::forward<Args>(problem)...));
}

}  // namespace ht
