// Command-line parsing for style4d subcommands: --name value, --name=value, boolean flags and
// positionals; old spellings of an option (one deprecation line each); group headings for --help.
// Unknown options (with the nearest known one), missing values and bad values are UsageErrors,
// which main reports in one line and exits 2 for.
#pragma once
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace s4d::cli {

// A command line the program cannot run as given: main exits 2 for it (other errors exit 1).
struct UsageError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

struct OptionSpec {
  std::string name;  // without dashes; empty: a group heading, `help` its title
  std::string help;
  bool takes_value = true;
  std::string value_name = "VALUE";
  std::vector<std::string> old_names = {};  // earlier spellings, still accepted with a deprecation line
};

// A heading in --help above the options that follow it.
inline OptionSpec group(const std::string& title) { return {"", title, false, ""}; }

// Thrown by Args on the hidden argument --list-options: a command's option table, for the shell
// completion (style4d completion bash), taken without running the command.
struct OptionTable {
  std::vector<OptionSpec> specs;
};

class Args {
 public:
  // Throws UsageError on an unknown option or a missing value. "--help" / "-h" sets help().
  Args(const std::vector<std::string>& argv, const std::vector<OptionSpec>& specs);

  bool help() const { return help_; }
  bool flag(const std::string& name) const { return flags_.count(name) > 0; }
  std::optional<std::string> get(const std::string& name) const;
  std::string get_or(const std::string& name, const std::string& fallback) const;
  // Every value given for `name`, in command-line order (get() returns the last).
  std::vector<std::string> get_all(const std::string& name) const;
  // Throws UsageError "missing required option --name".
  std::string require(const std::string& name) const;
  const std::vector<std::string>& positionals() const { return positionals_; }
  // The spelling the last value of `name` was given with ("out" for --out where the option is "run").
  std::string spelling(const std::string& name) const;

 private:
  bool help_ = false;
  std::set<std::string> flags_;
  std::map<std::string, std::string> values_, spellings_;
  std::map<std::string, std::vector<std::string>> all_values_;
  std::vector<std::string> positionals_;
};

// One line on stderr: "style4d: warning: OLD is an old spelling; use NEW (OLD keeps working)".
void warn_deprecated(const std::string& old_spelling, const std::string& new_spelling);

// The candidate nearest to `word` by edit distance, when it is near enough to be a likely typo;
// empty otherwise.
std::string nearest(const std::string& word, const std::vector<std::string>& candidates);

// Whole-string integer parse: "10x" or "" is an error naming the option, never a silent 10.
template <typename T>
T parse_number(const std::string& option, const std::string& text) {
  T value{};
  std::istringstream in(text);
  if (text.empty() || (std::is_unsigned_v<T> && text[0] == '-') || !(in >> value) || !in.eof())
    throw UsageError("--" + option + ": expected a" + (std::is_unsigned_v<T> ? " non-negative integer" : "n integer") +
                     ", got '" + text + "'");
  return value;
}

// A duration in seconds: "90", "90s", "20m", "1h30m", "1.5h" (units h, m, s, each at most once, in
// that order); positive. An error naming the option otherwise.
double parse_duration(const std::string& option, const std::string& text);

// "WxH" with both positive; an error naming the option otherwise.
std::pair<int, int> parse_size(const std::string& option, const std::string& text);

// Throws UsageError "unexpected argument 'X'" for the first positional, if any.
void refuse_positionals(const Args& args);

// "usage: style4d NAME ARGS\n\nSUMMARY\n\noptions:\n  --x VALUE  help..." with a section per group.
std::string usage(const std::string& command, const std::string& synopsis, const std::string& summary,
                  const std::vector<OptionSpec>& specs);

}  // namespace s4d::cli
