#include "core/byte_size.h"

#include <cctype>
#include <cstdio>
#include <stdexcept>

namespace ht {

std::string format_bytes(uint64_t b) {
    char s[64];
    if (b >= (uint64_t(1) << 30)) std::snprintf(s, sizeof s, "%.2f GiB", double(b) / double(uint64_t(1) << 30));
    else if (b >= (uint64_t(1) << 20)) std::snprintf(s, sizeof s, "%.1f MiB", double(b) / double(1 << 20));
    else std::snprintf(s, sizeof s, "%llu bytes", (unsigned long long)b);
    return s;
}

uint64_t parse_bytes(const std::string& text) {
    if (text.empty()) throw std::invalid_argument("empty size");
    size_t pos = 0;
    double v = std::stod(text, &pos);
    std::string unit = text.substr(pos);
    for (char& c : unit) c = char(std::toupper((unsigned char)c));
    if (!unit.empty() && unit.back() == 'B') unit.pop_back();
    if (!unit.empty() && unit.back() == 'I') unit.pop_back();
    double scale = 1;
    if (unit == "K") scale = 1024.0;
    else if (unit == "M") scale = 1024.0 * 1024;
    else if (unit == "G") scale = 1024.0 * 1024 * 1024;
    else if (unit == "T") scale = 1024.0 * 1024 * 1024 * 1024;
    else if (!unit.empty()) throw std::invalid_argument("unknown size unit in '" + text + "'");
    if (!(v > 0) || v * scale > 1.8e19) throw std::invalid_argument("size out of range: '" + text + "'");
    return uint64_t(v * scale);
}

}  // namespace ht
