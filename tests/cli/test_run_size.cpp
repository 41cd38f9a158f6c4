// The size a run's checkpoint is estimated at before training starts (run_size.h, the room check of
// `style4d train`) against the checkpoint the shared 4DGS run actually wrote.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <cstdint>
#include <fstream>

#include "run4d_fixture.h"
#include "s4d/run/checkpoint.h"
#include "s4d/run/run_size.h"

using namespace s4d;

TEST_CASE("the checkpoint size estimated from the settings matches a 4DGS run's checkpoint") {
  const test::Run4d& r = test::run4d();
  std::ifstream in(r.run / "run.json");
  const run::TrainConfig config = run::config_from_json(nlohmann::json::parse(in).at("settings"), "run.json");
  const std::filesystem::path file = r.run / "checkpoint" / "state.s4dckpt";
  const run::Checkpoint cp = run::read_checkpoint(file);
  const uint64_t actual = std::filesystem::file_size(file);
  const uint64_t estimate = run::checkpoint_bytes(config, static_cast<uint32_t>(cp.cloud.size()));
  INFO("estimate ", estimate, " actual ", actual, " Gaussians ", cp.cloud.size());
  // The arrays are counted exactly; only the JSON header is estimated, at 64 KiB (measured 8,745
  // bytes here). The file: 8-byte magic, u64 header length, u64 header checksum, header, arrays.
  std::ifstream raw(file, std::ios::binary);
  uint64_t header = 0;
  raw.seekg(8);
  raw.read(reinterpret_cast<char*>(&header), 8);
  CHECK(estimate - 65536 == actual - 24 - header);
  CHECK(estimate >= actual);
}
