// unisph: particle and sparse-grid simulation on CPU threads and NVIDIA GPUs.
#include <cstdio>
#include <exception>

#include <optional>

#include "commands.hpp"
#include "unisph/comm/communicator.hpp"
#include "unisph/core/error.hpp"
#include "unisph/exec/policy.hpp"

namespace unisph::app {

void add_execution_options(CLI::App& command, ExecutionOptions& options) {
  command.add_option("--policy", options.policy, "where kernels run: seq (one CPU thread), par (all CPU threads), "
                                                 "device (the CUDA GPU)")
      ->check(CLI::IsMember({"seq", "par", "device"}))
      ->capture_default_str();
  command.add_option("--threads", options.threads, "CPU threads for the par policy (0: all)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str()
      ->each([](const std::string& value) { set_host_threads(std::stoi(value)); });
}

}  // namespace unisph::app

int main(int argc, char** argv) {
  CLI::App app{"unisph: particle and sparse-grid simulation (SPH) on CPU threads and NVIDIA GPUs"};
  app.require_subcommand(1);
  unisph::app::add_info_command(app);
  unisph::app::add_demo_command(app);
  unisph::app::add_geometry_command(app);
  unisph::app::add_levelset_command(app);
  unisph::app::add_run_command(app);
  unisph::app::add_generate_command(app);
  // Under mpirun (unisph run on several ranks, docs/multi_gpu.md) MPI is started; otherwise not,
  // and unisph starts as fast as without MPI.
  std::optional<unisph::comm::Environment> mpi;
  if (unisph::comm::launched_by_mpi()) mpi.emplace(argc, argv);
  const unisph::comm::Communicator world = unisph::comm::Communicator::world();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return world.rank() == 0 ? app.exit(e) : e.get_exit_code();
  } catch (const unisph::comm::RankFailure& e) {
    // A collective check failed: every rank knows; rank 0 says it once.
    if (world.rank() == 0) std::fprintf(stderr, "unisph: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    // On several ranks one line naming the rank, and the others are ended wherever they wait.
    if (world.size() > 1) world.abort(std::string("error: ") + e.what());
    std::fprintf(stderr, "unisph: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
