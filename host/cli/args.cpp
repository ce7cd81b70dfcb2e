#include "cli/args.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace ht {

ArgParser& ArgParser::flag(const std::string& name, const std::string& help) {
    order_.push_back(name);
    specs_[name] = Spec{"", help, "", false, false};
    return *this;
}

ArgParser& ArgParser::option(const std::string& name, const std::string& value_name,
                             const std::string& help, const std::string& default_value, bool repeatable) {
    order_.push_back(name);
    specs_[name] = Spec{value_name, help, default_value, true, repeatable};
    return *this;
}

ArgParser& ArgParser::positional(const std::string& name, const std::string& help, bool required) {
    positional_specs_.push_back({name, help});
    positional_required_.push_back(required);
    return *this;
}

void ArgParser::parse(const std::vector<std::string>& args) {
    size_t pos_index = 0;
    for (size_t i = 0; i < args.size(); ++i) {
        std::string a = args[i];
        if (a.size() > 1 && a[0] == '-' && !(a.size() > 1 && (std::isdigit((unsigned char)a[1]) || a[1] == '.'))) {
            std::string value;
            bool inline_value = false;
            auto eq = a.find('=');
            if (eq != std::string::npos) {
                value = a.substr(eq + 1);
                a = a.substr(0, eq);
                inline_value = true;
            }
            auto it = specs_.find(a);
            if (it == specs_.end()) throw UsageError(command_ + ": unknown option '" + a + "' (see --help)");
            if (it->second.takes_value) {
                if (!inline_value) {
                    if (i + 1 >= args.size()) throw UsageError(command_ + ": option " + a + " needs a value <" + it->second.value_name + ">");
                    value = args[++i];
                }
                auto& v = values_[a];
                if (!v.empty() && !it->second.repeatable)
                    throw UsageError(command_ + ": option " + a + " given twice");
                v.push_back(value);
            } else {
                if (inline_value) throw UsageError(command_ + ": option " + a + " takes no value");
                values_[a].push_back("1");
            }
        } else {
            if (pos_index >= positional_specs_.size())
                throw UsageError(command_ + ": unexpected argument '" + a + "' (see --help)");
            values_[positional_specs_[pos_index++].first].push_back(a);
        }
    }
    if (has("--help")) return;
    for (size_t p = pos_index; p < positional_specs_.size(); ++p)
        if (positional_required_[p])
            throw UsageError(command_ + ": missing argument <" + positional_specs_[p].first + "> (see --help)");
}

bool ArgParser::has(const std::string& name) const { return values_.count(name) > 0; }

std::string ArgParser::get(const std::string& name) const {
    auto it = values_.find(name);
    if (it != values_.end()) return it->second.back();
    auto s = specs_.find(name);
    return s == specs_.end() ? std::string() : s->second.default_value;
}

std::vector<std::string> ArgParser::all(const std::string& name) const {
    auto it = values_.find(name);
    return it == values_.end() ? std::vector<std::string>{} : it->second;
}

int ArgParser::get_int(const std::string& name, long lo, long hi) const {
    std::string s = get(name);
    errno = 0;
    char* end = nullptr;
    long v = std::strtol(s.c_str(), &end, 10);
    if (s.empty() || *end || errno)
        throw UsageError(command_ + ": " + name + " expects an integer, got '" + s + "'");
    if (v < lo || v > hi)
        throw UsageError(command_ + ": " + name + " = " + s + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return int(v);
}

double ArgParser::get_double(const std::string& name, double lo, double hi) const {
    std::string s = get(name);
    char* end = nullptr;
    double v = std::strtod(s.c_str(), &end);
    if (s.empty() || *end || !std::isfinite(v))
        throw UsageError(command_ + ": " + name + " expects a number, got '" + s + "'");
    if (v < lo || v > hi) {
        std::ostringstream m;
        m << command_ << ": " << name << " = " << s << " is outside [" << lo << ", " << hi << "]";
        throw UsageError(m.str());
    }
    return v;
}

std::string ArgParser::help() const {
    std::ostringstream o;
    o << "usage: hairtrace " << command_;
    for (size_t i = 0; i < positional_specs_.size(); ++i)
        o << (positional_required_[i] ? " <" : " [<") << positional_specs_[i].first << (positional_required_[i] ? ">" : ">]");
    o << " [options]\n";
    for (auto& p : positional_specs_) o << "  <" << p.first << ">\n      " << p.second << "\n";
    if (!order_.empty()) o << "options:\n";
    for (auto& n : order_) {
        const Spec& s = specs_.at(n);
        o << "  " << n;
        if (s.takes_value) o << " <" << s.value_name << ">";
        o << "\n      " << s.help;
        if (!s.default_value.empty()) o << " (default: " << s.default_value << ")";
        if (s.repeatable) o << " (repeatable)";
        o << "\n";
    }
    return o.str();
}

}  // namespace ht
