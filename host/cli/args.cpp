#include "cli/args.h"

#include "cli/path_checks.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace ht {

namespace {

size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            const size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
            diagonal = up;
        }
    }
    return row[b.size()];
}

// A value that starts with '-' is still a value when it is a number ("--seed -1" is refused by
// the range check, not mistaken for an option).
bool looks_like_option(const std::string& a) {
    return a.size() > 1 && a[0] == '-' && !std::isdigit((unsigned char)a[1]) && a[1] != '.';
}

// Help text wrapped to the terminal width people read help in.
void append_wrapped(std::ostringstream& o, const std::string& text, size_t indent, size_t width = 100) {
    std::istringstream words(text);
    std::string word;
    size_t column = indent;
    o << std::string(indent, ' ');
    bool first = true;
    while (words >> word) {
        if (!first && column + 1 + word.size() > width) {
            o << "\n" << std::string(indent, ' ');
            column = indent;
            first = true;
        }
        if (!first) {
            o << ' ';
            ++column;
        }
        o << word;
        column += word.size();
        first = false;
    }
    o << "\n";
}

}  // namespace

std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates) {
    // A shortened name ("--theta" for "--theta-deg") is closer than any edit distance says.
    std::string shortest_extension;
    for (const std::string& c : candidates)
        if (word.size() >= 4 && c.size() > word.size() && c.compare(0, word.size(), word) == 0 &&
            (shortest_extension.empty() || c.size() < shortest_extension.size()))
            shortest_extension = c;
    if (!shortest_extension.empty()) return " (did you mean " + shortest_extension + "?)";
    std::string best;
    size_t best_distance = std::string::npos;
    for (const std::string& c : candidates) {
        const size_t d = edit_distance(word, c);
        if (d < best_distance) {
            best_distance = d;
            best = c;
        }
    }
    // A third of the word may be mistyped, at least two letters: "--sp" -> "--spp", "-spp" ->
    // "--spp", "--heigth" -> "--height"; "--bogus" suggests nothing.
    const size_t tolerated = std::max<size_t>(2, word.size() / 3);
    return best_distance <= tolerated ? " (did you mean " + best + "?)" : "";
}

ArgParser::ArgParser(std::string command, std::string summary)
    : command_(std::move(command)), summary_(std::move(summary)) {}

ArgParser::Spec& ArgParser::declare(const std::string& name, Spec spec) {
    spec.group = group_;
    order_.push_back(name);
    return specs_[name] = std::move(spec);
}

ArgParser& ArgParser::group(const std::string& title) {
    group_ = title;
    return *this;
}

ArgParser& ArgParser::flag(const std::string& name, const std::string& help) {
    declare(name, Spec{"", help, "", "", false, false, std::nullopt});
    return *this;
}

ArgParser& ArgParser::option(const std::string& name, const std::string& value_name, const std::string& help,
                             const std::string& default_value, bool repeatable) {
    declare(name, Spec{value_name, help, default_value, "", true, repeatable, std::nullopt});
    return *this;
}

ArgParser& ArgParser::path(const std::string& name, const std::string& value_name, const std::string& help,
                           PathKind kind, const std::string& default_value, bool repeatable) {
    declare(name, Spec{value_name, help, default_value, "", true, repeatable, kind});
    return *this;
}

ArgParser& ArgParser::positional(const std::string& name, const std::string& help, Arity arity) {
    positionals_.push_back({name, help, arity});
    return *this;
}

ArgParser& ArgParser::epilog(const std::string& text) {
    epilog_ = text;
    return *this;
}

std::vector<std::string> ArgParser::names() const {
    std::vector<std::string> n = order_;
    n.push_back("--help");
    return n;
}

UsageError ArgParser::error(const std::string& name, const std::string& problem) const {
    return UsageError(command_ + ": " + name + " " + problem);
}

void ArgParser::take_option(const std::vector<std::string>& args, size_t& i) {
    std::string name = args[i], value;
    const auto eq = name.find('=');
    const bool inline_value = eq != std::string::npos;
    if (inline_value) {
        value = name.substr(eq + 1);
        name = name.substr(0, eq);
    }
    const auto it = specs_.find(name);
    if (it == specs_.end())
        throw UsageError(command_ + ": unknown option " + name + did_you_mean(name, names()) + "; hairtrace " +
                         command_ + " --help lists them all");
    const Spec& spec = it->second;
    if (!spec.takes_value) {
        if (inline_value) throw error(name, "takes no value");
        value = "1";
    } else if (!inline_value) {
        if (i + 1 >= args.size()) throw error(name, "needs a value " + spec.value_name);
        value = args[++i];
    }
    auto& values = values_[name];
    if (!values.empty() && !spec.repeatable) throw error(name, "is given twice");
    values.push_back(value);
    given_.push_back({name, value});
}

void ArgParser::parse(const std::vector<std::string>& args) {
    // Asking for help is never a mistake, whatever else the line holds.
    for (const std::string& a : args)
        if (a == "--help" || a == "-h") {
            values_["--help"].push_back("1");
            return;
        }
    size_t positional = 0;
    for (size_t i = 0; i < args.size(); ++i) {
        if (looks_like_option(args[i])) {
            take_option(args, i);
            continue;
        }
        if (positional >= positionals_.size())
            throw UsageError(command_ + ": unexpected argument '" + args[i] + "'; hairtrace " + command_ +
                             " --help shows the usage");
        values_[positionals_[positional].name].push_back(args[i]);
        if (positionals_[positional].arity != Arity::Many) ++positional;
    }
    for (const Positional& p : positionals_)
        if (p.arity != Arity::Optional && !has(p.name))
            throw UsageError(command_ + ": missing argument " + p.name + "; hairtrace " + command_ +
                             " --help shows the usage");
    check_paths();
}

void ArgParser::check_paths() const {
    for (const auto& [name, value] : given_) {
        const Spec& spec = specs_.at(name);
        if (spec.path) check_path(command_ + ": " + name, value, *spec.path);
    }
    for (const auto& [name, spec] : specs_)
        if (spec.path && !spec.default_value.empty() && !has(name))
            check_path(command_ + ": " + name + " (default)", spec.default_value, *spec.path);
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

int parse_int(const std::string& what, const std::string& text, long lo, long hi) {
    errno = 0;
    char* end = nullptr;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end || errno) throw UsageError(what + " expects an integer, got '" + text + "'");
    if (v < lo || v > hi)
        throw UsageError(what + " = " + text + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return int(v);
}

double parse_double(const std::string& what, const std::string& text, double lo, double hi) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end || !std::isfinite(v)) throw UsageError(what + " expects a number, got '" + text + "'");
    if (v < lo || v > hi) {
        std::ostringstream m;
        m << what << " = " << text << " is outside [" << lo << ", " << hi << "]";
        throw UsageError(m.str());
    }
    return v;
}

double parse_auto_off_or_double(const std::string& what, const std::string& text, double lo, double hi,
                                double auto_value) {
    if (text == "auto") return auto_value;
    if (text == "off") return 0.0;
    try {
        return parse_double(what, text, lo, hi);
    } catch (const UsageError&) {
        std::ostringstream m;
        m << what << " must be auto, off or a number in [" << lo << ", " << hi << "], got '" << text << "'";
        throw UsageError(m.str());
    }
}

std::vector<std::string> split_fields(const std::string& text, char sep) {
    std::vector<std::string> fields;
    size_t start = 0;
    for (;;) {
        const size_t end = text.find(sep, start);
        fields.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
        if (end == std::string::npos) return fields;
        start = end + 1;
    }
}

std::string shell_words(const std::vector<std::string>& words) {
    std::string line;
    for (const std::string& w : words) {
        if (!line.empty()) line += ' ';
        const bool plain = !w.empty() && w.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                             "0123456789-_.,:/=+@%") == std::string::npos;
        if (plain) {
            line += w;
            continue;
        }
        line += '\'';
        for (char c : w) line += c == '\'' ? std::string("'\\''") : std::string(1, c);
        line += '\'';
    }
    return line;
}

std::vector<double> parse_number_list(const std::string& what, const std::string& text, size_t count,
                                      const char* form) {
    const UsageError error(what + " expects " + form + " numbers, got '" + text + "'");
    const std::vector<std::string> items = split_fields(text, ',');
    if (items.size() != count) throw error;
    std::vector<double> v;
    for (const std::string& item : items) {
        try {
            v.push_back(parse_double(what, item, -HUGE_VAL, HUGE_VAL));
        } catch (const UsageError&) {
            throw error;
        }
    }
    return v;
}

const std::string& require_choice(const std::string& what, const std::string& value,
                                  const std::vector<std::string>& choices) {
    for (const std::string& c : choices)
        if (c == value) return c;
    std::string list;
    for (size_t i = 0; i < choices.size(); ++i) list += (i ? i + 1 == choices.size() ? " or " : ", " : "") + choices[i];
    throw UsageError(what + " must be " + list + ", got '" + value + "'" + did_you_mean(value, choices));
}

int ArgParser::get_int(const std::string& name, long lo, long hi) const {
    return parse_int(command_ + ": " + name, get(name), lo, hi);
}

double ArgParser::get_double(const std::string& name, double lo, double hi) const {
    return parse_double(command_ + ": " + name, get(name), lo, hi);
}

std::string ArgParser::get_choice(const std::string& name, const std::vector<std::string>& choices) const {
    return require_choice(command_ + ": " + name, get(name), choices);
}

std::optional<int> ArgParser::get_int_or(const std::string& name, const std::string& keyword, long lo, long hi) const {
    if (get(name) == keyword) return std::nullopt;
    try {
        return get_int(name, lo, hi);
    } catch (const UsageError&) {
        throw error(name, "must be " + keyword + " or an integer in [" + std::to_string(lo) + ", " +
                              std::to_string(hi) + "], got '" + get(name) + "'");
    }
}

std::optional<double> ArgParser::get_double_or(const std::string& name, const std::string& keyword, double lo,
                                               double hi) const {
    if (get(name) == keyword) return std::nullopt;
    try {
        return get_double(name, lo, hi);
    } catch (const UsageError&) {
        std::ostringstream m;
        m << "must be " << keyword << " or a number in [" << lo << ", " << hi << "], got '" << get(name) << "'";
        throw error(name, m.str());
    }
}

std::string ArgParser::help() const {
    std::ostringstream o;
    o << "usage: hairtrace " << command_;
    for (const Positional& p : positionals_)
        o << (p.arity == Arity::Optional ? " [" : " ") << p.name << (p.arity == Arity::Many ? "..." : "")
          << (p.arity == Arity::Optional ? "]" : "");
    o << " [options]\n";
    if (!summary_.empty()) o << summary_ << (summary_.back() == '\n' ? "" : "\n");
    if (!positionals_.empty()) o << "\narguments:\n";
    for (const Positional& p : positionals_) {
        o << "  " << p.name << "\n";
        append_wrapped(o, p.help, 6);
    }
    // Groups in the order of their first option; options declared before any group first.
    std::vector<std::string> groups;
    for (const std::string& n : order_)
        if (std::find(groups.begin(), groups.end(), specs_.at(n).group) == groups.end())
            groups.push_back(specs_.at(n).group);
    for (const std::string& g : groups) {
        o << "\n" << (g.empty() ? "options" : g) << ":\n";
        for (const std::string& n : order_) {
            const Spec& s = specs_.at(n);
            if (s.group != g) continue;
            o << "  " << n << (s.takes_value ? " " + s.value_name : "") << "\n";
            std::string text = s.help;
            if (!s.default_value.empty()) text += " (default: " + s.default_value + ")";
            if (s.repeatable) text += " (repeatable)";
            append_wrapped(o, text, 6);
        }
    }
    o << "\n  --help, -h\n      this help\n";
    if (!epilog_.empty()) o << "\n" << epilog_ << (epilog_.back() == '\n' ? "" : "\n");
    return o.str();
}

}  // namespace ht
