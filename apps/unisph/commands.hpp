#pragma once
// One function per subcommand: it adds the subcommand, its options and its action to the app.
#include <CLI/CLI.hpp>

namespace unisph::app {

// Options every subcommand that runs kernels shares: --policy and --threads.
struct ExecutionOptions {
  std::string policy = "par";
  int threads = 0;
};
void add_execution_options(CLI::App& command, ExecutionOptions& options);

void add_info_command(CLI::App& app);
void add_demo_command(CLI::App& app);
void add_geometry_command(CLI::App& app);
void add_levelset_command(CLI::App& app);
void add_run_command(CLI::App& app);
void add_generate_command(CLI::App& app);

}  // namespace unisph::app
