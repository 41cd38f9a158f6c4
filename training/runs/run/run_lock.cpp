// The run lock (run_lock.h). Holder pids come from /proc/locks, which lists every flock with its
// owner's pid and the file's device and inode, so shared holders are found too; the pid an
// exclusive holder writes into the file is the fallback where /proc is not mounted.
#include "s4d/run/run_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

namespace s4d::run {

namespace fs = std::filesystem;

namespace {

// The pid of a process holding a flock on the file open as `fd`, or 0 when none is found.
long holder_pid(int fd) {
  struct stat st {};
  if (::fstat(fd, &st) != 0) return 0;
  char id[64];
  std::snprintf(id, sizeof id, "%02x:%02x:%llu", major(st.st_dev), minor(st.st_dev),
                static_cast<unsigned long long>(st.st_ino));
  std::ifstream locks("/proc/locks");
  std::string line;
  while (std::getline(locks, line)) {
    // "1: FLOCK  ADVISORY  WRITE 1234 08:01:5678 0 EOF"; waiters carry "->" after the number.
    std::istringstream in(line);
    std::string ordinal, kind, advisory, access, pid, file;
    in >> ordinal >> kind;
    if (kind == "->") in >> kind;
    if (!(in >> advisory >> access >> pid >> file) || kind != "FLOCK" || file != id) continue;
    const long p = std::strtol(pid.c_str(), nullptr, 10);
    if (p > 0) return p;
  }
  char text[32] = {};
  if (::pread(fd, text, sizeof text - 1, 0) > 0) return std::strtol(text, nullptr, 10);
  return 0;
}

}  // namespace

RunLock::RunLock(const fs::path& dir, Mode mode) : file_(dir / ".lock") {
  if (!fs::is_directory(dir)) throw std::runtime_error(dir.string() + ": not a directory (nothing to lock)");
  const int op = (mode == Mode::exclusive ? LOCK_EX : LOCK_SH) | LOCK_NB;
  while (true) {
    // O_CLOEXEC: a child process (a video encoder) must not inherit, and so prolong, the lock.
    fd_ = ::open(file_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw std::runtime_error("cannot open " + file_.string() + ": " + std::strerror(errno));
    if (::flock(fd_, op) != 0) {
      const int err = errno;
      const long pid = err == EWOULDBLOCK ? holder_pid(fd_) : 0;
      ::close(fd_);
      fd_ = -1;
      if (err != EWOULDBLOCK) throw std::runtime_error("cannot lock " + file_.string() + ": " + std::strerror(err));
      throw RunLocked(dir.string() + ": locked by another style4d process (pid " +
                      (pid > 0 ? std::to_string(pid) : std::string("unknown")) + ")");
    }
    // The holder before may have removed the file (release(true)) between our open and flock: then
    // this lock is on a file nobody else will open. Take it again on the file now at the path.
    struct stat held {}, named {};
    if (::fstat(fd_, &held) == 0 && ::stat(file_.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
        held.st_ino == named.st_ino)
      break;
    ::close(fd_);
    fd_ = -1;
  }
  if (mode == Mode::exclusive) {  // for people reading the file; holder_pid prefers /proc/locks
    const std::string pid = std::to_string(::getpid()) + "\n";
    if (::ftruncate(fd_, 0) == 0) {
      const ssize_t written = ::pwrite(fd_, pid.data(), pid.size(), 0);
      static_cast<void>(written);  // only informative: the lock is what counts
    }
  }
}

RunLock::~RunLock() { release(); }

RunLock::RunLock(RunLock&& other) noexcept : file_(std::move(other.file_)), fd_(other.fd_) { other.fd_ = -1; }

RunLock& RunLock::operator=(RunLock&& other) noexcept {
  if (this != &other) {
    release();
    file_ = std::move(other.file_);
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}

void RunLock::release(bool remove_file) {
  if (fd_ < 0) return;
  if (remove_file) ::unlink(file_.c_str());
  ::close(fd_);  // drops the flock
  fd_ = -1;
}

bool empty_but_for_lock(const fs::path& dir) {
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
    if (e.path().filename() != ".lock") return false;
  return !ec;
}

}  // namespace s4d::run
