// The style4d subcommands. Each takes its arguments (after the subcommand name) and returns the
// process exit code; errors are thrown and reported by main as one line.
#pragma once
#include <string>
#include <vector>

namespace s4d::cli {

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
