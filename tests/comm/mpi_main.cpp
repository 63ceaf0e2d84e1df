// main() of the communication tests: MPI up before GoogleTest, oneTBB threads capped so that
// the ranks of one node share its cores (UNISPH_THREADS_PER_RANK, else cores / ranks on the node).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <thread>

#include "unisph/comm/communicator.hpp"
#include "unisph/exec/policy.hpp"

int main(int argc, char** argv) {
  unisph::comm::Environment environment(argc, argv);
  const unisph::comm::Communicator comm = unisph::comm::Communicator::world();
  // One GPU per rank of a node (NCCL refuses two ranks on one GPU), before anything touches it.
  unisph::select_device(comm.local_rank());
  int threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()) / comm.local_size());
  if (const char* t = std::getenv("UNISPH_THREADS_PER_RANK")) threads = std::max(1, std::atoi(t));
  unisph::set_host_threads(threads);
  ::testing::InitGoogleTest(&argc, argv);
  // Failures are printed by the rank that sees them; the other ranks keep going (the tests
  // make every collective call on every rank, whatever the checks say).
  return RUN_ALL_TESTS();
}
