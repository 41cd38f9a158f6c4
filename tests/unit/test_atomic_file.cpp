#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "s4d/util/atomic_file.h"

namespace fs = std::filesystem;

namespace {
std::string read(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}
}  // namespace

TEST_CASE("atomic writes replace the file and leave no temporaries") {
  const fs::path dir = fs::temp_directory_path() / "s4d_atomic_file_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path target = dir / "result.json";
  s4d::util::write_file_atomic(target, "{\"a\": 1}");
  CHECK(read(target) == "{\"a\": 1}");
  s4d::util::write_file_atomic(target, "{\"a\": 2}");
  CHECK(read(target) == "{\"a\": 2}");
  CHECK(std::distance(fs::directory_iterator(dir), fs::directory_iterator()) == 1);
  fs::remove_all(dir);
}

TEST_CASE("a failed atomic write names the path") {
  CHECK_THROWS_WITH_AS(s4d::util::write_file_atomic("/nonexistent-dir/x.json", "x"),
                       doctest::Contains("/nonexistent-dir/x.json"), std::runtime_error);
}

TEST_CASE("a log whose stream failed is refused by name") {
  std::ofstream closed;  // never opened: every write fails
  closed << "x";
  CHECK_THROWS_WITH_AS(s4d::util::require_written(closed, "run/loss.csv"), doctest::Contains("cannot write run/loss.csv"),
                       std::runtime_error);
  std::ostringstream fine;
  fine << "x";
  CHECK_NOTHROW(s4d::util::require_written(fine, "run/loss.csv"));
}
