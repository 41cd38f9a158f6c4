// The style4d subcommands and their table. Each takes its arguments (after the subcommand name)
// and returns the process exit code; errors are thrown and reported by main as one line. They live
// in the s4d_commands library, so that tests call them, and what they are built from, in process.
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace s4d::cli {

struct Command {
  const char* name;
  const char* summary;  // style4d --help's line
  std::function<int(const std::vector<std::string>&)> run;
};

// Every subcommand, in style4d --help's order.
const std::vector<Command>& command_table();
// The command named `name`; null when there is none.
const Command* find_command(const std::string& name);

int cmd_bench(const std::vector<std::string>& args);
int cmd_check_data(const std::vector<std::string>& args);
int cmd_devices(const std::vector<std::string>& args);
int cmd_export_ply(const std::vector<std::string>& args);
int cmd_demo(const std::vector<std::string>& args);
int cmd_make_style(const std::vector<std::string>& args);
int cmd_render(const std::vector<std::string>& args);
int cmd_stylize(const std::vector<std::string>& args);
int cmd_stylize_frames(const std::vector<std::string>& args);
int cmd_study(const std::vector<std::string>& args);
int cmd_sweep(const std::vector<std::string>& args);
int cmd_synth(const std::vector<std::string>& args);
int cmd_train(const std::vector<std::string>& args);
int cmd_train_stylizer(const std::vector<std::string>& args);
int cmd_view(const std::vector<std::string>& args);

}  // namespace s4d::cli
