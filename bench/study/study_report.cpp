#include "s4d/study/study_report.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "s4d/study/study_stats.h"
#include "s4d/util/atomic_file.h"

namespace s4d::study {

namespace {

// Why a participant's vote on an attention check fails it, or empty when it passes.
std::string check_failure(const Item& it, const Vote& v) {
  if (it.check == "identical" && v.chosen != "same") return "chose a side of two identical videos";
  if (it.check == "broken" && v.chosen != it.methods[it.intact]) return "did not choose the intact video over the broken one";
  return "";
}

std::string percent(double share) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", 100 * share);
  return buf;
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

}  // namespace

nlohmann::json study_report_json(const Study& study, const std::vector<Vote>& votes) {
  // Attention checks first: who is out, and why.
  std::set<std::string> voted, excluded;
  nlohmann::json failures = nlohmann::json::array();
  for (const Vote& v : votes) {
    voted.insert(v.participant);
    const Item& it = study.item(v.item);
    if (it.check.empty()) continue;
    if (const std::string why = check_failure(it, v); !why.empty()) {
      excluded.insert(v.participant);
      failures.push_back({{"participant", v.participant}, {"item", v.item}, {"check", it.check}, {"criterion", v.criterion},
                          {"chosen", v.chosen}, {"why", why}});
    }
  }

  struct Table {
    std::string part, kind, criterion;
    std::vector<std::string> methods;
    std::map<std::string, std::map<std::string, int>> wins;  // winner -> loser -> count
    int decisive = 0, ties = 0;
    std::map<std::string, std::vector<std::string>> units;   // item -> the values participants chose
  };
  std::vector<Table> tables;
  auto table = [&](const Item& it, const std::string& criterion) -> Table& {
    for (Table& t : tables)
      if (t.part == it.part && t.kind == it.kind && t.criterion == criterion) return t;
    tables.push_back({it.part, it.kind, criterion, {}, {}, 0, 0, {}});
    return tables.back();
  };
  // Every method of a part and kind has a row, including one that never won.
  for (const Part& part : study.parts)
    for (const char* kind : {"video", "frame"})
      for (const Item& it : study.items) {
        if (it.part != part.id || it.kind != kind || !it.check.empty()) continue;
        for (const Criterion& c : it.criteria()) {
          Table& t = table(it, c.id);
          for (const std::string& m : it.methods)
            if (std::find(t.methods.begin(), t.methods.end(), m) == t.methods.end()) t.methods.push_back(m);
        }
      }
  for (Table& t : tables) std::sort(t.methods.begin(), t.methods.end());
  for (const Vote& v : votes) {
    const Item& it = study.item(v.item);
    if (!it.check.empty() || excluded.count(v.participant)) continue;
    Table& t = table(it, v.criterion);
    t.units[v.item].push_back(v.chosen);
    if (v.chosen == "same") {
      ++t.ties;
      continue;
    }
    ++t.decisive;
    ++t.wins[v.chosen][v.chosen == it.methods[0] ? it.methods[1] : it.methods[0]];
  }

  nlohmann::json out_tables = nlohmann::json::array();
  for (const Table& t : tables) {
    const size_t m = t.methods.size();
    std::vector<std::vector<int>> matrix(m, std::vector<int>(m, 0));
    for (size_t i = 0; i < m; ++i)
      for (size_t j = 0; j < m; ++j)
        if (auto a = t.wins.find(t.methods[i]); a != t.wins.end())
          if (auto b = a->second.find(t.methods[j]); b != a->second.end()) matrix[i][j] = b->second;
    const BradleyTerry bt = bradley_terry(matrix, t.methods);
    nlohmann::json rows = nlohmann::json::array();
    for (size_t i = 0; i < m; ++i) {
      int w = 0;
      for (int x : matrix[i]) w += x;
      const Interval ci = wilson_interval(w, t.decisive);
      nlohmann::json row = {{"method", t.methods[i]}, {"wins", w}, {"ci95", {ci.low, ci.high}}};
      row["share"] = t.decisive > 0 ? nlohmann::json(static_cast<double>(w) / t.decisive) : nlohmann::json(nullptr);
      if (!bt.strength.empty()) row["bradley_terry"] = bt.strength[i];
      rows.push_back(row);
    }
    std::vector<std::vector<std::string>> units;
    for (const auto& [item, values] : t.units) units.push_back(values);
    const std::optional<double> alpha = krippendorff_alpha_nominal(units);
    nlohmann::json entry = {{"part", t.part}, {"kind", t.kind}, {"criterion", t.criterion}, {"votes", t.decisive},
                            {"ties", t.ties}, {"methods", rows}};
    if (bt.strength.empty()) entry["bradley_terry"] = {{"unavailable", t.decisive == 0 ? std::string("no votes") : bt.why}};
    else entry["bradley_terry"] = {{"iterations", bt.iterations}};
    entry["krippendorff_alpha"] = alpha ? nlohmann::json(*alpha)
                                        : nlohmann::json{{"unavailable", "no item has two votes that differ in any unit, or no item "
                                                                         "has two votes at all: agreement is undefined"}};
    out_tables.push_back(entry);
  }
  nlohmann::json parts = nlohmann::json::array();
  for (const Part& p : study.parts) parts.push_back({{"id", p.id}, {"title", p.title}});
  return {{"format", "style4d-study-report/1"},
          {"interval", "Wilson score interval, 95 % (z = 1.96), of each share of the decisive votes"},
          {"share", "votes for the method / decisive votes (\"same\" answers are counted as ties and left out)"},
          {"bradley_terry", "strengths summing to 1, maximum likelihood by Hunter's MM iteration"},
          {"krippendorff_alpha", "nominal; units are the pairs, values the method chosen (or same), raters the participants"},
          {"participants", {{"planned", study.participants.size()}, {"voted", voted.size()}, {"excluded", excluded.size()},
                            {"included", voted.size() - excluded.size()},
                            {"excluded_codes", std::vector<std::string>(excluded.begin(), excluded.end())}}},
          {"check_failures", failures},
          {"parts", parts},
          {"tables", out_tables}};
}

void write_study_report(const std::filesystem::path& out, const nlohmann::json& r) {
  std::filesystem::create_directories(out);
  util::write_file_atomic(out / "study_report.json", r.dump(1) + "\n");

  std::ostringstream csv;
  csv << "part,kind,criterion,method,wins,votes,ties,share,ci95_low,ci95_high,bradley_terry\n";
  for (const auto& t : r.at("tables"))
    for (const auto& row : t.at("methods")) {
      csv << csv_field(t.at("part")) << "," << t.at("kind").get<std::string>() << "," << t.at("criterion").get<std::string>() << ","
          << csv_field(row.at("method")) << "," << row.at("wins") << "," << t.at("votes") << "," << t.at("ties") << ",";
      csv << (row.at("share").is_null() ? "" : row.at("share").dump()) << "," << row.at("ci95")[0] << "," << row.at("ci95")[1] << ","
          << (row.contains("bradley_terry") ? row.at("bradley_terry").dump() : "") << "\n";
    }
  util::write_file_atomic(out / "study_report.csv", csv.str());

  // The paper's layout: per part, a row per method and a column per criterion, each cell a vote share.
  std::ostringstream md;
  const auto& people = r.at("participants");
  md << "# User study\n\n"
     << people.at("included") << " participants counted of " << people.at("voted") << " who voted (" << people.at("planned")
     << " planned); " << people.at("excluded") << " excluded for failing an attention check.\n\n"
     << "Each cell: the method's share of the decisive votes, with the 95 % Wilson score interval in brackets. "
     << "\"Same\" answers are ties, left out of the shares. BT: Bradley-Terry strength (sums to 1 per column).\n";
  for (const auto& part : r.at("parts")) {
    std::vector<const nlohmann::json*> cols;
    for (const auto& t : r.at("tables"))
      if (t.at("part") == part.at("id")) cols.push_back(&t);
    if (cols.empty()) continue;
    md << "\n## " << part.at("title").get<std::string>() << "\n\n| method |";
    for (const auto* t : cols) md << " " << t->at("criterion").get<std::string>() << " (" << t->at("kind").get<std::string>() << "s) |";
    md << "\n|---|";
    for (size_t k = 0; k < cols.size(); ++k) md << "---|";
    md << "\n";
    std::vector<std::string> methods;  // every method of the part, in the tables' (sorted) order
    for (const auto* t : cols)
      for (const auto& row : t->at("methods"))
        if (std::find(methods.begin(), methods.end(), row.at("method")) == methods.end()) methods.push_back(row.at("method"));
    std::sort(methods.begin(), methods.end());
    for (const std::string& method : methods) {
      md << "| " << method << " |";
      for (const auto* t : cols) {
        const nlohmann::json* row = nullptr;
        for (const auto& candidate : t->at("methods"))
          if (candidate.at("method") == method) row = &candidate;
        if (!row || row->at("share").is_null()) {
          md << " n/a (" << (row ? "no votes" : "not in these pairs") << ") |";
          continue;
        }
        md << " " << percent(row->at("share")) << " % [" << percent(row->at("ci95")[0]) << ", " << percent(row->at("ci95")[1]) << "]";
        if (row->contains("bradley_terry")) {
          char bt[32];
          std::snprintf(bt, sizeof bt, "%.3f", row->at("bradley_terry").get<double>());
          md << ", BT " << bt;
        }
        md << " |";
      }
      md << "\n";
    }
    md << "| votes (ties) |";
    for (const auto* t : cols) md << " " << t->at("votes") << " (" << t->at("ties") << ") |";
    md << "\n| Krippendorff's alpha |";
    for (const auto* t : cols) {
      const auto& a = t->at("krippendorff_alpha");
      char buf[32];
      if (a.is_number()) std::snprintf(buf, sizeof buf, "%.3f", a.get<double>());
      md << " " << (a.is_number() ? std::string(buf) : "n/a") << " |";
    }
    md << "\n";
    for (const auto* t : cols) {
      const auto& bt = t->at("bradley_terry");
      if (bt.contains("unavailable"))
        md << "\nBradley-Terry of " << t->at("criterion").get<std::string>() << " (" << t->at("kind").get<std::string>()
           << "s): n/a, because " << bt.at("unavailable").get<std::string>() << ".";
      const auto& a = t->at("krippendorff_alpha");
      if (!a.is_number())
        md << "\nKrippendorff's alpha of " << t->at("criterion").get<std::string>() << " (" << t->at("kind").get<std::string>()
           << "s): n/a, because " << a.at("unavailable").get<std::string>() << ".";
    }
    md << "\n";
  }
  if (!r.at("check_failures").empty()) {
    md << "\n## Attention-check failures\n\n| participant | check | criterion | chose | why |\n|---|---|---|---|---|\n";
    for (const auto& f : r.at("check_failures"))
      md << "| " << f.at("participant").get<std::string>() << " | " << f.at("check").get<std::string>() << " | "
         << f.at("criterion").get<std::string>() << " | " << f.at("chosen").get<std::string>() << " | " << f.at("why").get<std::string>()
         << " |\n";
  }
  util::write_file_atomic(out / "study_report.md", md.str());
}

}  // namespace s4d::study
