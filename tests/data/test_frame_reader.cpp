// The one reader of frame sequences (s4d/data/frame_reader.h): a folder of PNG frames in name order
// whatever their channels, a video to the end of its stream, and the errors naming the file.
#include <doctest/doctest.h>

#include <stdexcept>

#include "data_test_util.h"
#include "s4d/data/frame_reader.h"
#include "s4d/data/video_writer.h"

using namespace s4d;

namespace {

// An image of `channels` channels whose every value is level / 255.
io::ImageF flat(int width, int height, int channels, int level) {
  return {width, height, channels, std::vector<float>(size_t(width) * height * channels, float(level) / 255.0f)};
}

}  // namespace

TEST_CASE("a folder of PNG frames is read in name order as RGB; other files are skipped") {
  test::TempDir dir("frame_reader_folder");
  const auto folder = dir / "frames";
  std::filesystem::create_directories(folder);
  io::write_png(folder / "0002.png", flat(6, 4, 4, 30));  // RGBA: alpha dropped
  io::write_png(folder / "0000.png", flat(6, 4, 3, 10));
  io::write_png(folder / "0001.PNG", flat(6, 4, 1, 20));  // gray, upper-case extension: replicated
  test::write_raw(folder / "notes.txt", "not a frame");
  data::FrameReader reader(folder);
  REQUIRE(reader.size() == 3);
  CHECK(reader.files()[1].filename() == "0001.PNG");
  for (int level : {10, 20, 30}) {
    const io::ImageF f = reader.next_counted();
    REQUIRE(f.channels == 3);
    CHECK(f.data == flat(6, 4, 3, level).data);  // 8-bit levels read back exactly as v / 255
  }
  CHECK_FALSE(reader.next());
  CHECK_THROWS_WITH_AS(reader.next_counted(), (folder.string() + ": ends after 3 of the 3 frames declared").c_str(),
                       std::runtime_error);
}

TEST_CASE("frame reader errors name the path and what is wrong") {
  test::TempDir dir("frame_reader_errors");
  const auto folder = dir / "frames";
  std::filesystem::create_directories(folder);
  CHECK_THROWS_WITH_AS(data::FrameReader{folder}, (folder.string() + ": no PNG frames in the folder").c_str(),
                       std::runtime_error);
  CHECK_THROWS_WITH_AS(data::FrameReader{dir / "missing"}, ((dir / "missing").string() + ": no such folder or video").c_str(),
                       std::runtime_error);
  test::write_raw(dir / "frames.txt", "text");
  CHECK_THROWS_WITH_AS(data::FrameReader{dir / "frames.txt"},
                       ((dir / "frames.txt").string() + ": neither a folder of PNG frames nor a video (.mp4, .avi, .mov, .mkv)").c_str(),
                       std::runtime_error);
  io::write_png(folder / "a.png", flat(6, 4, 3, 10));
  io::write_png(folder / "b.png", flat(5, 4, 3, 10));
  data::FrameReader reader(folder);
  CHECK(reader.next());
  CHECK_THROWS_WITH_AS(reader.next(), ((folder / "b.png").string() + ": 5x4, but the first frame is 6x4").c_str(),
                       std::runtime_error);
}

TEST_CASE("a video is read to the end of its stream; its container declares the count") {
  test::TempDir dir("frame_reader_video");
  const auto path = dir / "clip.MP4";
  {
    data::VideoWriter writer(path, 16, 12);
    for (int k = 0; k < 4; ++k) writer.write(test::smooth_pattern(16, 12, k));
  }
  CHECK(data::is_video_path(path));
  data::FrameReader reader(path);
  CHECK(reader.size() == 4);
  CHECK(reader.files().empty());
  int frames = 0;
  while (const std::optional<io::ImageF> f = reader.next()) {
    CHECK(f->width == 16);
    CHECK(f->channels == 3);
    ++frames;
  }
  CHECK(frames == 4);
}
