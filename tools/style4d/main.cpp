// style4d: one program, one subcommand per job (docs/commands.md). Errors print one line
// "style4d COMMAND: error: ..." and exit 1; a command line that cannot run as given exits 2.
#include <csignal>
#include <exception>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "args.h"
#include "commands.h"
#include "completion.h"

namespace {

using s4d::cli::Command;
using s4d::cli::command_table;

// Handled by main itself, beside the command table.
const std::vector<std::string> kBuiltins = {"help", "completion"};

void print_help() {
  std::cout << "usage: style4d COMMAND [options]   (style4d help COMMAND, or style4d COMMAND --help, for details)\n\n"
               "Style4D on Vulkan: 4D Gaussian splatting, 4D stylization and the Style4D-Bench metrics.\n\n"
               "commands:\n";
  auto line = [](const std::string& name, const std::string& summary) {
    std::cout << "  " << name << std::string(name.size() < 16 ? 16 - name.size() : 1, ' ') << summary << "\n";
  };
  for (const auto& c : command_table()) line(c.name, c.summary);
  std::cout << "\nthe program:\n";
  line("help COMMAND", "a command's options, grouped (as COMMAND --help)");
  line("completion bash", "a bash completion script: source <(style4d completion bash)");
  line("--version", "the program's version");
  std::cout << "\nenvironment:\n"
               "  S4D_DEVICE=<index|name>   choose the Vulkan device (default: discrete > integrated > CPU)\n"
               "  S4D_VALIDATION=1          enable the Vulkan validation layer\n";
}

int unknown_command(const std::string& name) {
  std::vector<std::string> names = kBuiltins;
  for (const auto& c : command_table()) names.emplace_back(c.name);
  const std::string near = s4d::cli::nearest(name, names);
  std::cerr << "style4d: error: unknown command '" << name << "'" << (near.empty() ? "" : "; did you mean '" + near + "'?")
            << " (style4d --help lists the commands)\n";
  return 2;
}

int completion(const std::vector<std::string>& args) {
  if (args.size() != 1 || args[0] != "bash") {
    std::cerr << "style4d completion: error: expected the shell: style4d completion bash (bash is the one supported)\n";
    return 2;
  }
  std::vector<s4d::cli::CommandEntry> entries;
  for (const auto& c : command_table()) entries.push_back({c.name, c.run});
  std::cout << s4d::cli::bash_completion(entries, kBuiltins);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // Past the file-size limit (ulimit -f) a write should fail and be reported by name like a full
  // disk, not kill the process halfway through a file.
  std::signal(SIGXFSZ, SIG_IGN);
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || (args[0] == "help" && args.size() == 1)) {
    print_help();
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "--version") {
    std::cout << "style4d " << S4D_VERSION << "\n";
    return 0;
  }
  if (args[0] == "completion") return completion({args.begin() + 1, args.end()});
  if (args[0] == "help") {  // help COMMAND: the command's own --help
    if (args.size() != 2) {
      std::cerr << "style4d help: error: expected one command: style4d help COMMAND\n";
      return 2;
    }
    args = {args[1], "--help"};
  }
  const std::string name = args[0];
  args.erase(args.begin());
  const Command* c = s4d::cli::find_command(name);
  if (!c) return unknown_command(name);
  try {
    return c->run(args);
  } catch (const s4d::cli::UsageError& e) {
    std::cerr << "style4d " << name << ": error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "style4d " << name << ": error: " << e.what() << "\n";
    return 1;
  } catch (const s4d::cli::OptionTable& table) {  // --list-options (the completion asks it): one option a line
    for (const auto& o : table.specs)
      if (!o.name.empty()) std::cout << "--" << o.name << "\n";
    return 0;
  }
}
