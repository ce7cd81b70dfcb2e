#include "cl/kernel_source.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace ht {

const std::vector<std::pair<std::string, std::string>>& embedded_kernel_files();

namespace {
std::string& dir_override() {
    static std::string dir = [] {
        const char* env = std::getenv("HAIRTRACE_KERNEL_DIR");
        return std::string(env ? env : "");
    }();
    return dir;
}

std::string dirname_of(const std::string& p) {
    auto slash = p.rfind('/');
    return slash == std::string::npos ? std::string() : p.substr(0, slash + 1);
}

// "a/b/../c.h" -> "a/c.h"
std::string normalize_path(const std::string& p) {
    std::vector<std::string> parts;
    std::stringstream ss(p);
    std::string item;
    while (std::getline(ss, item, '/')) {
        if (item.empty() || item == ".") continue;
        if (item == ".." && !parts.empty()) { parts.pop_back(); continue; }
        parts.push_back(item);
    }
    std::string out;
    for (size_t i = 0; i < parts.size(); ++i) out += (i ? "/" : "") + parts[i];
    return out;
}

bool file_exists(const std::string& rel) {
    if (!dir_override().empty()) return std::ifstream(dir_override() + "/" + rel).good();
    for (auto& f : embedded_kernel_files())
        if (f.first == rel) return true;
    return false;
}

// The directive a line holds ("if", "ifdef", "include", ...), or "" for none.
std::string directive_of(const std::string& line) {
    size_t p = line.find_first_not_of(" \t");
    if (p == std::string::npos || line[p] != '#') return "";
    p = line.find_first_not_of(" \t", p + 1);
    if (p == std::string::npos) return "";
    size_t e = p;
    while (e < line.size() && std::isalpha((unsigned char)line[e])) ++e;
    return line.substr(p, e - p);
}

// Inlines #include "..." recursively.  A header is inlined once it has been included
// unconditionally; an include inside #if/#ifdef/#ifndef (other than the header's own include
// guard) is inlined but does not count, because that block may be compiled out and a later
// unconditional include must still bring the header in (the include guards drop the repeat).
// `conditional`: this file itself was included inside such a block.
void assemble(const std::string& file, std::set<std::string>& once, std::vector<std::string>& stack,
              bool conditional, std::ostringstream& out) {
    if (stack.size() > 32) throw std::runtime_error("kernels/" + file + ": #include nesting too deep");
    std::istringstream in(kernel_file(file));
    std::string line;
    int line_no = 0, depth = 0, guard_depth = -1;
    bool first_directive = true;
    out << "#line 1 \"kernels/" << file << "\"\n";
    while (std::getline(in, line)) {
        ++line_no;
        const std::string d = directive_of(line);
        if (d == "if" || d == "ifdef" || d == "ifndef") {
            // the header's own guard (its first directive, #ifndef) does not make its body conditional
            if (first_directive && d == "ifndef") guard_depth = depth;
            ++depth;
        } else if (d == "endif") {
            --depth;
        }
        if (!d.empty()) first_directive = false;
        if (d == "include") {
            size_t q1 = line.find('"'), q2 = q1 == std::string::npos ? q1 : line.find('"', q1 + 1);
            if (q1 != std::string::npos && q2 != std::string::npos) {
                std::string name = line.substr(q1 + 1, q2 - q1 - 1);
                std::string rel = normalize_path(dirname_of(file) + name);
                if (!file_exists(rel)) rel = normalize_path(name);  // relative to kernels/
                const int open = depth - (guard_depth >= 0 ? 1 : 0);
                const bool in_block = conditional || open > 0;
                const bool on_stack = std::find(stack.begin(), stack.end(), rel) != stack.end();
                if (!once.count(rel) && !on_stack) {
                    if (!in_block) once.insert(rel);
                    stack.push_back(rel);
                    assemble(rel, once, stack, in_block, out);
                    stack.pop_back();
                }
                out << "#line " << (line_no + 1) << " \"kernels/" << file << "\"\n";
                continue;
            }
        }
        out << line << '\n';
    }
}

// The source with every comment replaced by a space (kernels hold no string literals that could
// contain comment markers), so that a define named in a comment does not count as read.
std::string without_comments(const std::string& src) {
    std::string out;
    out.reserve(src.size());
    for (size_t i = 0; i < src.size(); ++i) {
        if (src.compare(i, 2, "/*") == 0) {
            const size_t end = src.find("*/", i + 2);
            out += ' ';
            for (size_t k = i; k < std::min(end, src.size()); ++k)
                if (src[k] == '\n') out += '\n';  // keep lines: a directive ends at its line
            i = end == std::string::npos ? src.size() : end + 1;
        } else if (src.compare(i, 2, "//") == 0) {
            const size_t end = src.find('\n', i);
            out += ' ';
            i = end == std::string::npos ? src.size() : end - 1;
        } else {
            out += src[i];
        }
    }
    return out;
}

bool is_name_char(char c) { return std::isalnum((unsigned char)c) || c == '_'; }

// Whether `name` occurs in `source` as a whole word other than as its own default declaration,
// the first word after #ifndef or #define.
bool reads_name(const std::string& source, const std::string& name) {
    for (size_t at = source.find(name); at != std::string::npos; at = source.find(name, at + 1)) {
        const size_t end = at + name.size();
        if ((at > 0 && is_name_char(source[at - 1])) || (end < source.size() && is_name_char(source[end]))) continue;
        const size_t newline = at == 0 ? std::string::npos : source.rfind('\n', at - 1);
        const size_t line_start = newline == std::string::npos ? 0 : newline + 1;
        std::string head = source.substr(line_start, at - line_start);
        head.erase(std::remove_if(head.begin(), head.end(), [](char c) { return c == ' ' || c == '\t'; }), head.end());
        if (head != "#ifndef" && head != "#define") return true;
    }
    return false;
}
}  // namespace

std::string options_read_by(const std::string& source_text, const std::string& options) {
    const std::string source = without_comments(source_text);
    std::istringstream in(options);
    std::string tok, out;
    while (in >> tok) {
        if (tok.rfind("-D", 0) == 0 && tok.size() > 2 && !reads_name(source, tok.substr(2, tok.find('=') - 2)))
            continue;
        out += (out.empty() ? "" : " ") + tok;
    }
    return out;
}

void set_kernel_dir(const std::string& dir) { dir_override() = dir; }
const std::string& kernel_dir() { return dir_override(); }

std::string kernel_file(const std::string& rel_path) {
    if (!dir_override().empty()) {
        std::ifstream f(dir_override() + "/" + rel_path, std::ios::binary);
        if (!f) throw std::runtime_error("kernel file not found: " + dir_override() + "/" + rel_path);
        std::ostringstream s;
        s << f.rdbuf();
        return s.str();
    }
    for (auto& f : embedded_kernel_files())
        if (f.first == rel_path) return f.second;
    throw std::runtime_error("kernel file not embedded: kernels/" + rel_path);
}

std::string assemble_kernel_source(const std::string& main_file) {
    std::set<std::string> once{main_file};
    std::vector<std::string> stack{main_file};
    std::ostringstream out;
    assemble(main_file, once, stack, false, out);
    return out.str();
}

}  // namespace ht
