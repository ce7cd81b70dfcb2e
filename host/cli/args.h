// A small, strict command-line parser: every option is declared with its help text, unknown
// options and missing values are usage errors (exit 2), and --help prints the declared list.
#pragma once

#include "core/errors.h"

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace ht {

class ArgParser {
public:
    explicit ArgParser(std::string command) : command_(std::move(command)) {}

    // A flag takes no value; an option takes one (repeatable options keep every value).
    ArgParser& flag(const std::string& name, const std::string& help);
    ArgParser& option(const std::string& name, const std::string& value_name, const std::string& help,
                      const std::string& default_value = "", bool repeatable = false);
    ArgParser& positional(const std::string& name, const std::string& help, bool required = true);

    void parse(const std::vector<std::string>& args);  // throws UsageError

    bool has(const std::string& name) const;
    std::string get(const std::string& name) const;  // default when absent
    std::vector<std::string> all(const std::string& name) const;
    int get_int(const std::string& name, long lo, long hi) const;
    double get_double(const std::string& name, double lo, double hi) const;
    std::string help() const;

private:
    struct Spec {
        std::string value_name, help, default_value;
        bool takes_value = false, repeatable = false;
    };
    std::string command_;
    std::vector<std::string> order_;
    std::map<std::string, Spec> specs_;
    std::vector<std::pair<std::string, std::string>> positional_specs_;
    std::vector<bool> positional_required_;
    std::map<std::string, std::vector<std::string>> values_;
};

}  // namespace ht
