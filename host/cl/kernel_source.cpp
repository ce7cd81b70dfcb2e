#include "cl/kernel_source.h"

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

void assemble(const std::string& file, std::set<std::string>& once, std::ostringstream& out,
              int depth) {
    if (depth > 32) throw std::runtime_error("kernels/" + file + ": #include nesting too deep");
    std::istringstream in(kernel_file(file));
    std::string line;
    int line_no = 0;
    out << "#line 1 \"kernels/" << file << "\"\n";
    while (std::getline(in, line)) {
        ++line_no;
        size_t p = line.find_first_not_of(" \t");
        if (p != std::string::npos && line.compare(p, 8, "#include") == 0) {
            size_t q1 = line.find('"', p), q2 = q1 == std::string::npos ? q1 : line.find('"', q1 + 1);
            if (q1 != std::string::npos && q2 != std::string::npos) {
                std::string name = line.substr(q1 + 1, q2 - q1 - 1);
                std::string rel = normalize_path(dirname_of(file) + name);
                if (!file_exists(rel)) rel = normalize_path(name);  // relative to kernels/
                if (!once.count(rel)) {
                    once.insert(rel);
                    assemble(rel, once, out, depth + 1);
                }
                out << "#line " << (line_no + 1) << " \"kernels/" << file << "\"\n";
                continue;
            }
        }
        out << line << '\n';
    }
}
}  // namespace

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
    std::ostringstream out;
    assemble(main_file, once, out, 0);
    return out.str();
}

}  // namespace ht
