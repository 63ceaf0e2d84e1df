// A program that fails on one rank, for the error tests (tests/comm/expect_failure.sh):
//   collective   the last rank's check fails at a synchronisation point (check_all): every
//                rank stops, rank 0 prints one line naming the rank and the reason
//   abort        the last rank throws while the others wait in a collective: the top-level
//                handler prints one line and calls MPI_Abort, which ends the waiting ranks
// Both must end every rank with a non-zero status, never hang.
#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>

#include "unisph/comm/communicator.hpp"

int main(int argc, char** argv) {
  unisph::comm::Environment environment(argc, argv);
  const std::string mode = argc > 1 ? argv[1] : "collective";
  return unisph::comm::run_guarded(unisph::comm::Communicator::world(), [&](const unisph::comm::Communicator& comm) {
    const int failing = comm.size() - 1;
    for (int step = 0; step < 5; ++step) {
      if (mode == "collective") {
        std::string reason;
        bool ok = true;
        try {
          if (comm.rank() == failing && step == 3) throw std::runtime_error("the particle file ends at byte 1234");
        } catch (const std::exception& e) {
          ok = false;
          reason = e.what();
        }
        comm.check_all(ok, reason);
      } else {
        if (comm.rank() == failing && step == 3) throw std::runtime_error("the particle file ends at byte 1234");
        comm.barrier();
      }
    }
    return 0;
  });
}
