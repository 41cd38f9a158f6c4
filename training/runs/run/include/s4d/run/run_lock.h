// One writer per run folder: an advisory flock(2) on DIR/.lock, held by an open file descriptor for
// the lock's lifetime. The kernel drops it when the process ends however it ends (kill -9 included),
// so a lock is never stale. `style4d train` (new runs and --resume) holds a run's lock exclusively;
// `style4d stylize` holds it shared (the geometry must not change under a style; two styles of one
// run may train at once) and holds its style's folder exclusively.
#pragma once
#include <filesystem>
#include <stdexcept>

namespace s4d::run {

// "DIR: locked by another style4d process (pid N)".
struct RunLocked : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class RunLock {
 public:
  enum class Mode { exclusive, shared };

  // Takes the lock on `dir`/.lock without waiting; `dir` must exist (the file is created). Throws
  // RunLocked naming `dir` and the holder's pid when another open of the file holds a conflicting
  // lock (in this process too), std::runtime_error when the file cannot be opened. An exclusive
  // holder writes its pid into the file.
  explicit RunLock(const std::filesystem::path& dir, Mode mode = Mode::exclusive);
  ~RunLock();
  RunLock(RunLock&& other) noexcept;
  RunLock& operator=(RunLock&& other) noexcept;
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

  // Releases the lock; remove_file also deletes DIR/.lock first (safe: a process that opened the
  // old file notices it was unlinked and opens the new one).
  void release(bool remove_file = false);

  const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path file_;
  int fd_ = -1;
};

// Whether `dir` holds nothing but (at most) its .lock: what a new run may be created in.
bool empty_but_for_lock(const std::filesystem::path& dir);

}  // namespace s4d::run
