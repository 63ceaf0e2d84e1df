#pragma once
// The communication layer's view of the processes of a run: rank, size, collective reductions
// and the collective error check. MPI stays inside src/comm/: this header compiles without
// mpi.h, and where unisph was built without MPI (UNISPH_HAS_MPI = 0) every communicator is
// the serial one (rank 0 of 1), so that code above the layer compiles and runs unchanged.
//
// What the reductions guarantee (docs/multi_gpu.md):
//   allreduce_min / allreduce_max      exact; the same bits on every rank
//   allreduce_sum(std::uint64_t)       exact (modulo 2^64); the same on every rank
//   allreduce_sum(double x)            the rank values folded left to right in rank order,
//                                      ((x_0 + x_1) + x_2) + ..., computed on every rank from
//                                      the gathered values: the same bits on every rank of a
//                                      run. It depends on how the total was split into the
//                                      rank values, so it can differ between rank counts.
//   ordered_sum(span<const double>)    the sum of the global sequence (rank 0's values, then
//                                      rank 1's, ...), associated exactly as
//                                      deterministic_reduce(seq, n, Sum<double>{}, ...) over that
//                                      sequence on one rank: the same bits on every rank AND
//                                      for any rank count, as long as the global sequence holds
//                                      the same values in the same order. It gathers every value
//                                      to every rank (O(global count) traffic): for short series
//                                      (per-body totals, probes), not for per-particle fields.
//   combine_owned(span<double>)        each element owned by one rank, which passes its value
//                                      while the others pass 0: afterwards every rank holds the
//                                      owner's value with its bits (x + 0 = x however MPI
//                                      associates; -0 becomes +0). Measurements at points,
//                                      each taken by the rank that owns the point.
// NaN inputs propagate; min/max of an empty set is the identity (+inf / -inf, UINT64_MAX / 0).

#include <cstdint>
#include <cstdio>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "unisph/core/error.hpp"

namespace unisph::comm {

// Whether this unisph was built with MPI.
bool mpi_built();
// Whether this process was started by an MPI launcher (mpirun, mpiexec, srun): the launchers'
// environment variables (Open MPI's OMPI_COMM_WORLD_SIZE, PMI_SIZE, PMIX_RANK). A program that
// runs on one process as well makes an Environment only then, and starts as fast as before.
bool launched_by_mpi();

// Thrown on every rank by a collective check that failed on at least one rank. what() is one
// line naming the first failing rank and its reason, "rank 2: <reason>" (and, when more
// ranks failed, "(and 1 more rank)"); the same text on every rank.
class RankFailure : public Error {
 public:
  RankFailure(int rank, const std::string& line) : Error(line), rank_(rank) {}
  int failed_rank() const { return rank_; }

 private:
  int rank_;
};

// Initialises MPI (MPI_Init_thread, MPI_THREAD_FUNNELED: only the thread that made the
// Environment calls MPI) and finalises it when destroyed; without MPI it does nothing.
// One per process, in main, before any Communicator.
class Environment {
 public:
  Environment(int& argc, char**& argv);
  ~Environment();
  Environment(const Environment&) = delete;
  Environment& operator=(const Environment&) = delete;
};

class Communicator {
 public:
  // MPI_COMM_WORLD where MPI is built and initialised; the serial communicator otherwise.
  static Communicator world();
  // Rank 0 of 1, without MPI, whatever the build.
  static Communicator serial();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool is_serial() const { return impl_ == nullptr; }

  // Ranks on this node (MPI_Comm_split_type(MPI_COMM_TYPE_SHARED)): the local rank picks a GPU.
  int local_rank() const;
  int local_size() const;

  void barrier() const;

  double allreduce_min(double x) const;
  double allreduce_max(double x) const;
  double allreduce_sum(double x) const;
  std::uint64_t allreduce_min(std::uint64_t x) const;
  std::uint64_t allreduce_max(std::uint64_t x) const;
  std::uint64_t allreduce_sum(std::uint64_t x) const;
  // Elementwise sums of equal-length arrays (exact for integers), in place.
  void allreduce_sum(std::span<std::uint64_t> values) const;
  double ordered_sum(std::span<const double> local_values) const;
  // Each element from the one rank that owns it (the others pass 0), in place.
  void combine_owned(std::span<double> values) const;

  // Every rank's value, in rank order.
  std::vector<std::uint64_t> allgather(std::uint64_t x) const;
  std::vector<double> allgather(double x) const;
  // Every rank's values concatenated in rank order (lengths may differ between ranks).
  std::vector<double> allgatherv(std::span<const double> local) const;
  std::vector<std::uint64_t> allgatherv(std::span<const std::uint64_t> local) const;

  // send[r] values to rank r; returns recv[r], the value rank r sent here (MPI_Alltoall).
  std::vector<std::uint64_t> alltoall(std::span<const std::uint64_t> send) const;

  // Root's bytes to every rank (MPI_Bcast).
  void broadcast(void* data, std::size_t bytes, int root) const;

  // Point-to-point byte exchange, host memory: send[r] is sent to rank r and recv[r] is
  // filled from rank r (sizes agreed beforehand, e.g. by alltoall); r == rank() is a copy.
  // Non-blocking sends and receives, then one wait for all.
  struct Segment {
    void* data;
    std::size_t bytes;
  };
  void exchange(std::span<const Segment> send, std::span<const Segment> recv) const;

  // Collective: every rank calls it at the same point. When `ok` is false on any rank, every
  // rank throws RankFailure with the same line (the first failing rank and its message);
  // otherwise returns. One allgather of a flag, plus one of the messages only on failure.
  void check_all(bool ok, std::string_view message = {}) const;

  // Ends every rank of the run: writes `line` to stderr prefixed with the rank, then
  // MPI_Abort (std::abort without MPI). The last resort for a failure that other ranks
  // cannot learn about collectively (they may be waiting in a collective already).
  [[noreturn]] void abort(std::string_view line, int code = 1) const;

  // The MPI_Comm (as its address; nullptr for the serial communicator), for the transports.
  const void* native_handle() const;

  struct Impl;

 private:
  std::shared_ptr<Impl> impl_;
  int rank_ = 0;
  int size_ = 1;
};

// Runs body(communicator) on every rank and turns failures into one line per failure and a
// non-zero exit on every rank, never a hang:
//   RankFailure (a collective check failed): every rank knows; rank 0 prints
//     "unisph: <what>" and every rank returns 1;
//   any other exception on a rank: "unisph: rank R: <what>" on stderr, then MPI_Abort, which
//     ends the other ranks wherever they wait.
// Returns body's result (0 on success) on every rank.
template <class Body>
int run_guarded(const Communicator& comm, Body&& body) {
  try {
    return body(comm);
  } catch (const RankFailure& failure) {
    if (comm.rank() == 0) std::fprintf(stderr, "unisph: %s\n", failure.what());
    return 1;
  } catch (const std::exception& e) {
    comm.abort(e.what());
  } catch (...) {
    comm.abort("an exception of unknown type");
  }
}

}  // namespace unisph::comm
