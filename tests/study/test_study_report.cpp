// The study report from votes given by hand: attention-check failures excluded and counted, shares
// of the decisive votes with ties left out, and Bradley-Terry and Krippendorff values computed
// independently (pure Python, Newton's method and the pairwise form of alpha). Plus the vote
// store: one row per judgement, replays refused, rows kept across reopening.
#include <doctest/doctest.h>

#include <fstream>
#include <sstream>
#include <unistd.h>

#include "study_dirs.h"
#include "s4d/study/study_report.h"
#include "s4d/study/study_stats.h"
#include "s4d/study/vote_store.h"

using namespace s4d::study;
namespace fs = std::filesystem;

namespace {

using s4d::study::test::fresh;

// Methods A, B, C in Part 1: three video pairs, one frame pair, the two attention checks.
Study three_methods() {
  Study s;
  s.parts = {{"4d", "Part 1: 4D stylization"}};
  auto item = [](std::string id, std::string kind, std::string a, std::string b, std::string check = "") {
    return Item{id, "4d", kind, "scene", "style", "spiral", {a, b}, {"media/" + a, "media/" + b}, "", check, 0};
  };
  s.items = {item("v001", "video", "A", "B"), item("v002", "video", "A", "C"), item("v003", "video", "B", "C"),
             item("f001", "frame", "A", "B"), item("c001", "video", "A", "A", "identical"),
             item("c002", "video", "A", "A (broken)", "broken")};
  for (const char* code : {"P1", "P2", "P3", "P4"}) {
    Participant p{code, {}};
    for (const Item& it : s.items) p.order.push_back({it.id, false});
    s.participants.push_back(p);
  }
  return s;
}

Vote vote(std::string who, std::string item, std::string chosen, std::string criterion = "stylization") {
  return {who, item, criterion, chosen == "same" ? "same" : "left", chosen, false, 1, 2};
}

}  // namespace

TEST_CASE("study report: shares, ties, attention checks, Bradley-Terry, alpha") {
  const Study s = three_methods();
  std::vector<Vote> votes;
  for (const char* p : {"P1", "P2", "P3"}) {
    votes.push_back(vote(p, "c001", "same"));
    votes.push_back(vote(p, "c002", "A"));
  }
  // P4 prefers one of two identical videos: excluded, with the reason; its other votes count nowhere.
  votes.push_back(vote("P4", "c001", "A"));
  votes.push_back(vote("P4", "v001", "B"));
  votes.push_back(vote("P4", "v002", "C"));
  votes.push_back(vote("P4", "v003", "C"));
  votes.push_back(vote("P1", "v001", "A"));
  votes.push_back(vote("P1", "v002", "A"));
  votes.push_back(vote("P1", "v003", "B"));
  votes.push_back(vote("P2", "v001", "B"));
  votes.push_back(vote("P2", "v002", "A"));
  votes.push_back(vote("P2", "v003", "same"));
  votes.push_back(vote("P3", "v001", "A"));
  votes.push_back(vote("P3", "v002", "A"));
  votes.push_back(vote("P3", "v003", "C"));
  votes.push_back(vote("P1", "f001", "B", "image_quality"));

  const nlohmann::json r = study_report_json(s, votes);
  CHECK(r.at("participants").at("voted") == 4);
  CHECK(r.at("participants").at("excluded") == 1);
  CHECK(r.at("participants").at("included") == 3);
  CHECK(r.at("participants").at("excluded_codes") == nlohmann::json{"P4"});
  REQUIRE(r.at("check_failures").size() == 1);
  CHECK(r.at("check_failures")[0].at("check") == "identical");

  const nlohmann::json* table = nullptr;
  for (const auto& t : r.at("tables"))
    if (t.at("kind") == "video" && t.at("criterion") == "stylization") table = &t;
  REQUIRE(table);
  // Decisive votes: 9 judgements less the one tie. A won 5 (v001 twice, v002 three times), B 2, C 1.
  CHECK(table->at("votes") == 8);
  CHECK(table->at("ties") == 1);
  const auto& rows = table->at("methods");
  REQUIRE(rows.size() == 3);
  CHECK(rows[0].at("method") == "A");
  CHECK(rows[0].at("wins") == 5);
  CHECK(rows[0].at("share").get<double>() == 5.0 / 8);
  CHECK(rows[1].at("share").get<double>() == 2.0 / 8);
  CHECK(rows[2].at("share").get<double>() == 1.0 / 8);
  const Interval ci = wilson_interval(5, 8);
  CHECK(rows[0].at("ci95")[0].get<double>() == ci.low);
  // Wins A>B 2, B>A 1, A>C 3, B>C 1, C>B 1: Newton's method gives these strengths.
  CHECK(rows[0].at("bradley_terry").get<double>() == doctest::Approx(0.7099535123371304).epsilon(1e-9));
  CHECK(rows[1].at("bradley_terry").get<double>() == doctest::Approx(0.19594232059395306).epsilon(1e-9));
  CHECK(rows[2].at("bradley_terry").get<double>() == doctest::Approx(0.09410416706891667).epsilon(1e-9));
  // Units v001 {A, B, A}, v002 {A, A, A}, v003 {B, same, C}: alpha 0.2 by the pairwise formula.
  CHECK(table->at("krippendorff_alpha").get<double>() == doctest::Approx(0.2).epsilon(1e-12));

  // A criterion nobody answered: shares null and said so, not zero.
  for (const auto& t : r.at("tables"))
    if (t.at("kind") == "video" && t.at("criterion") == "consistency") {
      CHECK(t.at("votes") == 0);
      CHECK(t.at("methods")[0].at("share").is_null());
      CHECK(t.at("bradley_terry").at("unavailable") == "no votes");
    }

  const fs::path out = fresh("report");
  write_study_report(out, r);
  std::ifstream md(out / "study_report.md");
  std::stringstream text;
  text << md.rdbuf();
  CHECK(text.str().find("| A | 62.50 % [") != std::string::npos);
  CHECK(text.str().find("3 participants counted of 4 who voted") != std::string::npos);
  std::ifstream csv(out / "study_report.csv");
  std::string header;
  std::getline(csv, header);
  CHECK(header == "part,kind,criterion,method,wins,votes,ties,share,ci95_low,ci95_high,bradley_terry");
  fs::remove_all(out);
}

TEST_CASE("vote store: one row per judgement, replays change nothing, rows survive reopening") {
  const fs::path dir = fresh("store");
  {
    VoteStore store(dir / "votes.sqlite");
    CHECK(store.add({"P1", "v001", "stylization", "left", "A", true, 100, 200}) == AddResult::stored);
    CHECK(fs::exists(dir / "votes.sqlite-wal"));  // WAL mode
    CHECK(store.add({"P1", "v001", "stylization", "right", "B", true, 100, 300}) == AddResult::duplicate);
    CHECK(store.add({"P1", "v001", "consistency", "same", "same", true, 100, 300}) == AddResult::stored);
    CHECK(store.add({"P2", "v001", "stylization", "right", "B", false, 100, 300}) == AddResult::stored);
  }
  const VoteStore again(dir / "votes.sqlite", true);
  const std::vector<Vote> all = again.all();
  REQUIRE(all.size() == 3);
  CHECK(all[0].chosen == "A");  // the first answer stands
  CHECK(all[0].swap);
  CHECK(all[0].answered_ms == 200);
  CHECK(again.of_participant("P2").size() == 1);
  CHECK_THROWS_WITH_AS(VoteStore(dir / "none.sqlite", true), doctest::Contains("none.sqlite: no votes yet"), std::runtime_error);
  fs::remove_all(dir);
}
