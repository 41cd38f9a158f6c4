// FrameCache: memory stays within the budget, least recently used frames go first, and reloading
// gives the same data.
#include <doctest/doctest.h>

#include "data_test_util.h"
#include "s4d/data/frame_cache.h"

using namespace s4d;

TEST_CASE("frame cache evicts least recently used frames beyond its budget") {
  test::TempDir dir("cache_evict");
  const auto root = dir / "scene";
  test::write_dynerf(root, test::dynerf_cameras());
  const data::Dataset d = data::load_dynerf(root);
  const size_t frame_bytes = 16 * 12 * 3 * sizeof(float);
  data::FrameCache cache(d, 2 * frame_bytes);

  const std::vector<float> first = cache.get(d.views[0]).data;
  for (size_t i = 1; i < 4; ++i) {
    cache.get(d.views[i]);
    CHECK(cache.bytes() <= 2 * frame_bytes);
    CHECK(cache.frames() <= 2);
  }
  CHECK(cache.frames() == 2);
  CHECK(cache.get(d.views[0]).data == first);  // reloaded from disk

  // Views 0 and 3 are held now. Touch 3, then load 1: 0 is the least recently used and goes.
  cache.get(d.views[3]);
  cache.get(d.views[1]);
  std::filesystem::remove(d.views[0].image);
  std::filesystem::remove(d.views[3].image);
  CHECK(cache.get(d.views[3]).data.size() == 16 * 12 * 3);  // still cached: no disk access
  CHECK_THROWS_WITH_AS(cache.get(d.views[0]), doctest::Contains("0000.png"), std::runtime_error);
}

TEST_CASE("frame cache with a budget below one frame holds just the last one") {
  test::TempDir dir("cache_tiny");
  const auto root = dir / "scene";
  test::write_dynerf(root, test::dynerf_cameras(), 2);
  const data::Dataset d = data::load_dynerf(root);
  data::FrameCache cache(d, 1);
  const io::ImageF& a = cache.get(d.views[0]);
  CHECK(a.width == 16);
  CHECK(cache.frames() == 1);
  cache.get(d.views[1]);
  CHECK(cache.frames() == 1);
}
