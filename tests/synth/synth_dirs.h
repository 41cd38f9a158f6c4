// Where the synth tests write datasets: a path that does not exist yet, nor its ".partial" twin
// (write_dataset refuses an occupied destination).
#pragma once
#include <filesystem>
#include <string>

namespace s4d::synth::test {

inline std::filesystem::path fresh(const std::string& name) {
  const std::filesystem::path d = std::filesystem::temp_directory_path() / ("s4d_synth_" + name);
  std::filesystem::remove_all(d);
  std::filesystem::remove_all(std::filesystem::path(d) += ".partial");
  return d;
}

}  // namespace s4d::synth::test
