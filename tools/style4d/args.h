// Minimal command-line parsing for style4d subcommands: --name value, --name=value, boolean
// flags, and positionals. Unknown options and missing values are errors naming the option.
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

struct OptionSpec {
  std::string name;  // without dashes
  std::string help;
  bool takes_value = true;
  std::string value_name = "VALUE";
};

class Args {
 public:
  // Throws std::invalid_argument on an unknown option or a missing value. "--help" / "-h" sets help().
  Args(const std::vector<std::string>& argv, const std::vector<OptionSpec>& specs);

  bool help() const { return help_; }
  bool flag(const std::string& name) const { return flags_.count(name) > 0; }
  std::optional<std::string> get(const std::string& name) const;
  std::string get_or(const std::string& name, const std::string& fallback) const;
  // Every value given for `name`, in command-line order (get() returns the last).
  std::vector<std::string> get_all(const std::string& name) const;
  // Throws std::invalid_argument "missing required option --name".
  std::string require(const std::string& name) const;
  const std::vector<std::string>& positionals() const { return positionals_; }

 private:
  bool help_ = false;
  std::set<std::string> flags_;
  std::map<std::string, std::string> values_;
  std::map<std::string, std::vector<std::string>> all_values_;
  std::vector<std::string> positionals_;
};

// Whole-string integer parse: "10x" or "" is an error naming the option, never a silent 10.
template <typename T>
T parse_number(const std::string& option, const std::string& text) {
  T value{};
  std::istringstream in(text);
  if (text.empty() || (std::is_unsigned_v<T> && text[0] == '-') || !(in >> value) || !in.eof())
    throw std::invalid_argument("--" + option + ": expected a" +
                                (std::is_unsigned_v<T> ? " non-negative integer" : "n integer") + ", got '" + text + "'");
  return value;
}

// "WxH" with both positive; an error naming the option otherwise.
std::pair<int, int> parse_size(const std::string& option, const std::string& text);

// "usage: style4d NAME ARGS\n\nSUMMARY\n\noptions:\n  --x VALUE  help..."
std::string usage(const std::string& command, const std::string& synopsis, const std::string& summary,
                  const std::vector<OptionSpec>& specs);

}  // namespace s4d::cli
