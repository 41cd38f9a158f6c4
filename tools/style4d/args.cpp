#include "args.h"

#include <cctype>
#include <cmath>

#include <algorithm>
#include <iostream>
#include <sstream>

namespace s4d::cli {

Args::Args(const std::vector<std::string>& argv, const std::vector<OptionSpec>& specs) {
  if (argv.size() == 1 && argv[0] == "--list-options") throw OptionTable{specs};
  std::map<std::string, const OptionSpec*> by_name;
  std::vector<std::string> known;
  for (const auto& s : specs) {
    if (s.name.empty()) continue;  // a group heading
    for (const std::string& n : s.old_names) by_name[n] = &s;
    by_name[s.name] = &s;
    known.push_back(s.name);
  }
  std::set<std::string> warned;
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
    if (it == by_name.end()) {
      const std::string near = nearest(name, known);
      throw UsageError("unknown option --" + name + (near.empty() ? "" : "; did you mean --" + near + "?") + " (see --help)");
    }
    const OptionSpec& spec = *it->second;
    if (name != spec.name && warned.insert(name).second) warn_deprecated("--" + name, "--" + spec.name);
    if (!spec.takes_value) {
      if (inline_value) throw UsageError("option --" + name + " takes no value");
      flags_.insert(spec.name);
      continue;
    }
    if (!inline_value) {
      if (i + 1 >= argv.size()) throw UsageError("option --" + name + " needs a value");
      value = argv[++i];
    }
    values_[spec.name] = value;
    spellings_[spec.name] = name;
    all_values_[spec.name].push_back(value);
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
  if (!v) throw UsageError("missing required option --" + name + " (see --help)");
  return *v;
}

std::string Args::spelling(const std::string& name) const {
  auto it = spellings_.find(name);
  return it == spellings_.end() ? name : it->second;
}

void warn_deprecated(const std::string& old_spelling, const std::string& new_spelling) {
  std::cerr << "style4d: warning: " << old_spelling << " is an old spelling; use " << new_spelling << " (" << old_spelling
            << " keeps working)\n";
}

namespace {

// Edits from a to b: insertions, deletions, substitutions, and swaps of two neighbours ("trian").
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i)
    for (size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

}  // namespace

std::string nearest(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  size_t best_distance = 0;
  for (const std::string& c : candidates) {
    const size_t d = edit_distance(word, c);
    if (best.empty() || d < best_distance) best = c, best_distance = d;
  }
  // Two edits, or a third of a long word's letters: "--iter" finds --iters, "trian" train, "xyzzy" nothing.
  return !best.empty() && best_distance <= std::max<size_t>(2, word.size() / 3) ? best : std::string();
}

void refuse_positionals(const Args& args) {
  if (!args.positionals().empty()) throw UsageError("unexpected argument '" + args.positionals().front() + "'");
}

std::string usage(const std::string& command, const std::string& synopsis, const std::string& summary,
                  const std::vector<OptionSpec>& specs) {
  std::ostringstream s;
  s << "usage: style4d " << command << (synopsis.empty() ? "" : " ") << synopsis << "\n\n" << summary << "\n";
  if (specs.empty() || !specs.front().name.empty()) s << "\noptions:\n";
  for (const auto& o : specs) {
    if (o.name.empty()) {
      s << "\n" << o.help << ":\n";
      continue;
    }
    std::string left = "--" + o.name + (o.takes_value ? " " + o.value_name : "");
    s << "  " << left << std::string(left.size() < 22 ? 22 - left.size() : 1, ' ') << o.help;
    for (size_t i = 0; i < o.old_names.size(); ++i) s << (i == 0 ? " (old spelling: --" : ", --") << o.old_names[i];
    s << (o.old_names.empty() ? "" : ")") << "\n";
  }
  s << "  --help                " << "show this help\n";
  return s.str();
}

double parse_duration(const std::string& option, const std::string& text) {
  const auto bad = [&] {
    return UsageError("--" + option + ": expected a duration such as 90s, 20m or 1h30m, got '" + text + "'");
  };
  double seconds = 0;
  size_t at = 0;
  std::string units = "hms";  // the units still allowed, in order
  while (at < text.size()) {
    size_t used = 0;
    double value = 0;
    try {
      value = std::stod(text.substr(at), &used);
    } catch (const std::exception&) {
      throw bad();
    }
    if (used == 0 || !std::isfinite(value) || value < 0 || !std::isdigit(static_cast<unsigned char>(text[at]))) throw bad();
    at += used;
    if (at == text.size()) {  // a bare number: seconds, only on its own
      if (units != "hms") throw bad();
      seconds = value;
      break;
    }
    const size_t unit = units.find(text[at]);
    if (unit == std::string::npos) throw bad();
    seconds += value * (text[at] == 'h' ? 3600 : text[at] == 'm' ? 60 : 1);
    units.erase(0, unit + 1);
    ++at;
  }
  if (!(seconds > 0)) throw bad();
  return seconds;
}

std::pair<int, int> parse_size(const std::string& option, const std::string& text) {
  int w = 0, h = 0;
  char x = 0;
  std::istringstream in(text);
  if (!(in >> w >> x >> h) || x != 'x' || !in.eof() || w <= 0 || h <= 0)
    throw UsageError("--" + option + ": expected WxH (for example 160x120), got '" + text + "'");
  return {w, h};
}

}  // namespace s4d::cli
