#include <doctest/doctest.h>
#include <sys/resource.h>

#include <filesystem>
#include <stdexcept>

#include "s4d/util/free_space.h"

namespace fs = std::filesystem;

TEST_CASE("room to write: free space of the nearest existing folder, refused by name when short") {
  const fs::path missing = fs::temp_directory_path() / "s4d_free_space_not_made" / "run";
  const uint64_t free = s4d::util::free_bytes(missing);  // asks /tmp: the folder does not exist yet
  CHECK(free == s4d::util::free_bytes(fs::temp_directory_path()));
  CHECK_NOTHROW(s4d::util::require_room(missing, 1024, 1024, "a test"));
  CHECK_THROWS_WITH_AS(s4d::util::require_room(missing, free + (uint64_t{1} << 40), 0, "a test run"),
                       doctest::Contains("free, a test run needs about"), std::runtime_error);
}

TEST_CASE("room to write: a file-size limit (ulimit -f) below the largest file refuses") {
  struct rlimit saved {};
  REQUIRE(::getrlimit(RLIMIT_FSIZE, &saved) == 0);
  struct rlimit low = saved;
  low.rlim_cur = 1 << 20;
  if (saved.rlim_max != RLIM_INFINITY && saved.rlim_max < low.rlim_cur) low.rlim_cur = saved.rlim_max;
  REQUIRE(::setrlimit(RLIMIT_FSIZE, &low) == 0);
  CHECK(s4d::util::file_size_limit() == low.rlim_cur);
  CHECK_THROWS_WITH_AS(s4d::util::require_room(fs::temp_directory_path(), 0, 4 << 20, "a checkpoint"),
                       doctest::Contains("the file size limit (ulimit -f) is"), std::runtime_error);
  CHECK_NOTHROW(s4d::util::require_room(fs::temp_directory_path(), 0, low.rlim_cur, "a checkpoint"));
  REQUIRE(::setrlimit(RLIMIT_FSIZE, &saved) == 0);
}
