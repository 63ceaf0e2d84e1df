// `unisph info`: what this build and this machine offer.
#include <cstdio>

#include "commands.hpp"
#include "unisph/core/config.hpp"
#include "unisph/exec/policy.hpp"

namespace unisph::app {

void add_info_command(CLI::App& app) {
  CLI::App* command = app.add_subcommand("info", "print the execution policies this build and machine offer");
  command->callback([] {
    const ExecutionInfo& info = execution_info();
    std::printf("unisph %s, Real = %s\n", UNISPH_VERSION_STRING, sizeof(Real) == 8 ? "double" : "float");
    std::printf("  seq     available (1 CPU thread)\n");
    std::printf("  par     available (oneTBB, %d CPU threads)\n", host_threads());
    if (policy_available(PolicyKind::device))
      std::printf("  device  available (%s, %d multiprocessors, %.1f GiB)\n", info.device_name.c_str(),
                  info.device_multiprocessors, info.device_memory_gib);
    else
      std::printf("  device  not available: %s\n", info.device_unavailable_reason.c_str());
  });
}

}  // namespace unisph::app
