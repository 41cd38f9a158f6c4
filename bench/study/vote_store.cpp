#include "s4d/study/vote_store.h"

#include <sqlite3.h>

#include <stdexcept>

namespace s4d::study {

namespace {

const char* const kSchema =
    "CREATE TABLE IF NOT EXISTS votes ("
    " id INTEGER PRIMARY KEY,"
    " participant TEXT NOT NULL, item TEXT NOT NULL, criterion TEXT NOT NULL,"
    " choice TEXT NOT NULL CHECK (choice IN ('left', 'right', 'same')), chosen TEXT NOT NULL,"
    " swap INTEGER NOT NULL, shown_ms INTEGER NOT NULL, answered_ms INTEGER NOT NULL,"
    " UNIQUE (participant, item, criterion))";

// A prepared statement finalised on every path out.
struct Statement {
  sqlite3_stmt* s = nullptr;
  ~Statement() { sqlite3_finalize(s); }
};

}  // namespace

VoteStore::VoteStore(const std::filesystem::path& file, bool read_only) : file_(file) {
  if (read_only && !std::filesystem::exists(file))
    throw std::runtime_error(file.string() + ": no votes yet (`style4d study serve` creates it with the first participant)");
  const int flags = read_only ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE;
  if (sqlite3_open_v2(file.string().c_str(), &db_, flags | SQLITE_OPEN_FULLMUTEX, nullptr) != SQLITE_OK) {
    const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    throw std::runtime_error(file.string() + ": cannot open the vote database: " + why);
  }
  sqlite3_busy_timeout(db_, 5000);  // a report reading while the server writes waits, not fails
  const std::string setup = read_only ? "" : std::string("PRAGMA journal_mode=WAL; PRAGMA synchronous=FULL; ") + kSchema;
  char* error = nullptr;
  if (!setup.empty() && sqlite3_exec(db_, setup.c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
    const std::string why = error ? error : "unknown error";
    sqlite3_free(error);
    sqlite3_close(db_);
    throw std::runtime_error(file.string() + ": cannot set up the vote database: " + why);
  }
}

VoteStore::~VoteStore() { sqlite3_close(db_); }

AddResult VoteStore::add(const Vote& v) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st;
  const char* sql =
      "INSERT INTO votes (participant, item, criterion, choice, chosen, swap, shown_ms, answered_ms) "
      "VALUES (?, ?, ?, ?, ?, ?, ?, ?) ON CONFLICT (participant, item, criterion) DO NOTHING";
  if (sqlite3_prepare_v2(db_, sql, -1, &st.s, nullptr) != SQLITE_OK)
    throw std::runtime_error(file_.string() + ": " + sqlite3_errmsg(db_));
  int k = 0;
  for (const std::string* t : {&v.participant, &v.item, &v.criterion, &v.choice, &v.chosen})
    sqlite3_bind_text(st.s, ++k, t->c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_int(st.s, ++k, v.swap ? 1 : 0);
  sqlite3_bind_int64(st.s, ++k, v.shown_ms);
  sqlite3_bind_int64(st.s, ++k, v.answered_ms);
  if (sqlite3_step(st.s) != SQLITE_DONE) throw std::runtime_error(file_.string() + ": cannot store a vote: " + sqlite3_errmsg(db_));
  return sqlite3_changes(db_) == 1 ? AddResult::stored : AddResult::duplicate;
}

std::vector<Vote> VoteStore::query(const std::string& where, const std::string& arg) const {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement st;
  const std::string sql = "SELECT participant, item, criterion, choice, chosen, swap, shown_ms, answered_ms FROM votes " + where +
                          " ORDER BY id";
  if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &st.s, nullptr) != SQLITE_OK)
    throw std::runtime_error(file_.string() + ": " + sqlite3_errmsg(db_));
  if (!arg.empty()) sqlite3_bind_text(st.s, 1, arg.c_str(), -1, SQLITE_TRANSIENT);
  std::vector<Vote> out;
  int rc;
  auto text = [&](int c) { return std::string(reinterpret_cast<const char*>(sqlite3_column_text(st.s, c))); };
  while ((rc = sqlite3_step(st.s)) == SQLITE_ROW)
    out.push_back({text(0), text(1), text(2), text(3), text(4), sqlite3_column_int(st.s, 5) != 0, sqlite3_column_int64(st.s, 6),
                   sqlite3_column_int64(st.s, 7)});
  if (rc != SQLITE_DONE) throw std::runtime_error(file_.string() + ": cannot read the votes: " + sqlite3_errmsg(db_));
  return out;
}

std::vector<Vote> VoteStore::all() const { return query("", ""); }

std::vector<Vote> VoteStore::of_participant(const std::string& code) const { return query("WHERE participant = ?", code); }

}  // namespace s4d::study
