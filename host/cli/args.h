// The one command-line parser of every hairtrace command.  Each option is declared once with its
// help text (and, for paths, how the path is checked), so that --help, unknown options, bad
// values and bad paths are all answered the same way everywhere: --help/-h prints the complete
// list and exits 0; every mistake is a UsageError (exit 2) that names the option, the expected
// form and, for a misspelt option, the closest valid one.
#pragma once

#include "core/errors.h"

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace ht {

// How the value of a path option is checked by parse(), before any work starts.
enum class PathKind {
    Input,       // an existing file
    InputFolder, // an existing folder
    Image,       // an image OpenImageIO can write (by extension) in a writable folder
    Csv,         // a .csv file in a writable folder
    AnyOutput,   // a file of our own format (checkpoints): a writable folder
};

// How many values a positional argument takes.
enum class Arity { Required, Optional, Many };

// " (did you mean X?)" for the candidate closest to `word` by edit distance, or "" when none is
// close enough to be a likely typo.
std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates);

// Values outside an ArgParser (list items, key=value pairs); `what` names where they came from.
// Each throws a UsageError naming `what` and the expected form.
int parse_int(const std::string& what, const std::string& text, long lo, long hi);
double parse_double(const std::string& what, const std::string& text, double lo, double hi);
// "auto" -> auto_value, "off" -> 0, else a number in [lo, hi] (the settings whose auto a rule decides).
double parse_auto_off_or_double(const std::string& what, const std::string& text, double lo, double hi,
                                double auto_value);
// "a,,b," -> "a", "", "b", "": every field between separators, empty ones included (so that a
// stray separator is reported by whoever checks the fields).
std::vector<std::string> split_fields(const std::string& text, char sep);
// The words of a command line as a shell would take them back: words with spaces, quotes or
// other special characters single-quoted (the images' hairtrace:command_line).
std::string shell_words(const std::vector<std::string>& words);
// "a,b,c": exactly `count` finite numbers; `form` names them in the message ("x,y,z").
std::vector<double> parse_number_list(const std::string& what, const std::string& text, size_t count,
                                      const char* form);
const std::string& require_choice(const std::string& what, const std::string& value,
                                  const std::vector<std::string>& choices);

class ArgParser {
public:
    // `command` as typed after `hairtrace` ("render", "fiber eval"); `summary`: the first lines of
    // --help.  --help and -h are declared by every parser.
    explicit ArgParser(std::string command, std::string summary = "");

    // Options declared after group() are listed under `title` in --help.
    ArgParser& group(const std::string& title);
    // A flag takes no value; an option takes one (repeatable options keep every value).
    ArgParser& flag(const std::string& name, const std::string& help);
    ArgParser& option(const std::string& name, const std::string& value_name, const std::string& help,
                      const std::string& default_value = "", bool repeatable = false);
    // An option whose value (or default) is a path, checked by parse() as `kind` says.
    ArgParser& path(const std::string& name, const std::string& value_name, const std::string& help, PathKind kind,
                    const std::string& default_value = "", bool repeatable = false);
    ArgParser& positional(const std::string& name, const std::string& help, Arity arity = Arity::Required);
    // Text printed after the option list (exit codes, examples).
    ArgParser& epilog(const std::string& text);

    // Throws UsageError; with --help/-h anywhere among the arguments it only records that.
    void parse(const std::vector<std::string>& args);
    bool wants_help() const { return has("--help"); }
    std::string help() const;

    bool has(const std::string& name) const;
    std::string get(const std::string& name) const;  // the default when absent
    std::vector<std::string> all(const std::string& name) const;
    // Every option given, in command-line order (for options whose meaning depends on order).
    const std::vector<std::pair<std::string, std::string>>& given() const { return given_; }

    // Typed values; each throws a UsageError naming the option and the expected form.
    int get_int(const std::string& name, long lo, long hi) const;
    double get_double(const std::string& name, double lo, double hi) const;
    std::string get_choice(const std::string& name, const std::vector<std::string>& choices) const;
    // A number, or nullopt where the value is the word `keyword` ("auto", "off").
    std::optional<int> get_int_or(const std::string& name, const std::string& keyword, long lo, long hi) const;
    std::optional<double> get_double_or(const std::string& name, const std::string& keyword, double lo,
                                        double hi) const;
    // A UsageError about option `name` with this command's prefix.
    UsageError error(const std::string& name, const std::string& problem) const;

private:
    struct Spec {
        std::string value_name, help, default_value, group;
        bool takes_value = false, repeatable = false;
        std::optional<PathKind> path;
    };
    struct Positional {
        std::string name, help;
        Arity arity;
    };
    Spec& declare(const std::string& name, Spec spec);
    void take_option(const std::vector<std::string>& args, size_t& i);
    void check_paths() const;
    std::vector<std::string> names() const;

    std::string command_, summary_, epilog_, group_;
    std::vector<std::string> order_;
    std::map<std::string, Spec> specs_;
    std::vector<Positional> positionals_;
    std::map<std::string, std::vector<std::string>> values_;
    std::vector<std::pair<std::string, std::string>> given_;
};

}  // namespace ht
