// The study's votes in SQLite (STUDY/votes.sqlite), one row per judgement. WAL journal with
// synchronous=FULL: a vote is acknowledged only after its transaction is on disk, so it survives
// the server being killed (kill -9) or the machine losing power. One connection, its calls
// serialised, serves every request thread.
#pragma once
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

struct sqlite3;

namespace s4d::study {

struct Vote {
  std::string participant, item, criterion;
  std::string choice;  // the side clicked: "left", "right" or "same"
  std::string chosen;  // what that means: the method shown there, or "same"
  bool swap = false;   // the participant's placement of the item (media[1] on the left)
  int64_t shown_ms = 0, answered_ms = 0;  // Unix time in milliseconds: the page's and the server's clock
};

enum class AddResult { stored, duplicate };

class VoteStore {
 public:
  // Creates the file and its table when absent. read_only opens an existing store for reports.
  // Throws std::runtime_error naming the file.
  explicit VoteStore(const std::filesystem::path& file, bool read_only = false);
  ~VoteStore();
  VoteStore(const VoteStore&) = delete;
  VoteStore& operator=(const VoteStore&) = delete;

  // One judgement, committed before returning. A second vote of a participant on the same item and
  // criterion changes nothing and returns duplicate.
  AddResult add(const Vote& v);
  std::vector<Vote> all() const;                                  // in the order they were stored
  std::vector<Vote> of_participant(const std::string& code) const;

 private:
  std::vector<Vote> query(const std::string& where, const std::string& arg) const;
  std::filesystem::path file_;
  sqlite3* db_ = nullptr;
  mutable std::mutex mutex_;
};

}  // namespace s4d::study
