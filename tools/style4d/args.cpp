#include "args.h"

#include <sstream>
#include <stdexcept>

namespace s4d::cli {

Args::Args(const std::vector<std::string>& argv, const std::vector<OptionSpec>& specs) {
  std::map<std::string, const OptionSpec*> by_name;
  for (const auto& s : specs) by_name[s.name] = &s;
  for (size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    if (a == "--help" || a == "-h") {
      help_ = true;
      continue;
    }
    if (a.rfind("--", 0) != 0 || a.size() == 2) {
      positionals_.push_back(a);
      continue;
    }
    std::string name = a.substr(2), value;
    const size_t eq = name.find('=');
    const bool inline_value = eq != std::string::npos;
    if (inline_value) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
    }
    auto it = by_name.find(name);
    if (it == by_name.end()) throw std::invalid_argument("unknown option --" + name + " (see --help)");
    if (!it->second->takes_value) {
      if (inline_value) throw std::invalid_argument("option --" + name + " takes no value");
      flags_.insert(name);
      continue;
    }
    if (!inline_value) {
      if (i + 1 >= argv.size()) throw std::invalid_argument("option --" + name + " needs a value");
      value = argv[++i];
    }
    values_[name] = value;
    all_values_[name].push_back(value);
  }
}

std::optional<std::string> Args::get(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) return std::nullopt;
  return it->second;
}

std::string Args::get_or(const std::string& name, const std::string& fallback) const {
  return get(name).value_or(fallback);
}

std::vector<std::string> Args::get_all(const std::string& name) const {
  auto it = all_values_.find(name);
  return it == all_values_.end() ? std::vector<std::string>{} : it->second;
}

std::string Args::require(const std::string& name) const {
  auto v = get(name);
  if (!v) throw std::invalid_argument("missing required option --" + name + " (see --help)");
  return *v;
}

std::string usage(const std::string& command, const std::string& synopsis, const std::string& summary,
                  const std::vector<OptionSpec>& specs) {
  std::ostringstream s;
  s << "usage: style4d " << command << (synopsis.empty() ? "" : " ") << synopsis << "\n\n" << summary << "\n";
  s << "\noptions:\n";
  for (const auto& o : specs) {
    std::string left = "--" + o.name + (o.takes_value ? " " + o.value_name : "");
    s << "  " << left << std::string(left.size() < 22 ? 22 - left.size() : 1, ' ') << o.help << "\n";
  }
  s << "  --help                " << "show this help\n";
  return s.str();
}

std::pair<int, int> parse_size(const std::string& option, const std::string& text) {
  int w = 0, h = 0;
  char x = 0;
  std::istringstream in(text);
  if (!(in >> w >> x >> h) || x != 'x' || !in.eof() || w <= 0 || h <= 0)
    throw std::invalid_argument("--" + option + ": expected WxH (for example 160x120), got '" + text + "'");
  return {w, h};
}

}  // namespace s4d::cli
