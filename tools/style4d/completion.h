// `style4d completion bash`: a bash completion script generated from the commands' own option
// tables (Args's OptionTable), so that it never lists an option a command does not take.
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace s4d::cli {

struct CommandEntry {
  std::string name;
  std::function<int(const std::vector<std::string>&)> run;
};

// The script: command names after `style4d` and `style4d help`, each command's options after its
// name, file names after an option that takes a value.
std::string bash_completion(const std::vector<CommandEntry>& commands, const std::vector<std::string>& builtins);

}  // namespace s4d::cli
