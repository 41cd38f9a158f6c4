// Reading pictures of any common format (s4d/io/image_file.h): errors name the file.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include "s4d/io/image_file.h"

using namespace s4d;

TEST_CASE("reading an image names the file on failure") {
  const auto dir = std::filesystem::temp_directory_path() / "s4d_io_read_image";
  std::filesystem::create_directories(dir);
  CHECK_THROWS_WITH_AS(io::read_image_rgb(dir / "missing.png"), doctest::Contains("missing.png"), std::runtime_error);
  std::ofstream(dir / "junk.jpg") << "not an image";
  CHECK_THROWS_WITH_AS(io::read_image_rgb(dir / "junk.jpg"), doctest::Contains("junk.jpg"), std::runtime_error);
}
