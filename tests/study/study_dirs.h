// A fresh scratch folder per test process for the study tests.
#pragma once
#include <unistd.h>

#include <filesystem>
#include <string>

namespace s4d::study::test {

inline std::filesystem::path fresh(const std::string& name) {
  const std::filesystem::path d =
      std::filesystem::temp_directory_path() / ("s4d_study_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace s4d::study::test
