#pragma once
// A communication plan (Cabana's Distributor, AMReX's redistribute): built once from a list of
// (index, destination rank) pairs, it says which local items go where and how many arrive from
// whom, and then moves any number of arrays with those counts.
//
// Building it is collective: the items are ordered by destination rank (stably: items for one
// rank keep their order in the list), the counts are exchanged with MPI_Alltoall and the
// offsets are their exclusive scans. Received items are ordered by source rank, and within one
// source in that source's order. A pair whose destination is this rank is a copy to itself
// (a periodic image of a particle on its own rank).
//
// The plan keeps its lists on the host and, for the packing kernels, as variables readable in
// any memory space.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "unisph/comm/communicator.hpp"
#include "unisph/memory/discrete_variable.hpp"

namespace unisph::comm {

class Plan {
 public:
  // Collective. export_rank[k] in [0, comm.size()) is the destination of local item
  // export_index[k].
  Plan(const Communicator& comm, std::span<const std::uint32_t> export_index, std::span<const int> export_rank);

  int ranks() const { return ranks_; }
  int rank() const { return rank_; }
  Index export_count() const { return export_index_.size(); }
  Index import_count() const { return import_count_; }

  // Items per rank and their exclusive scans (ranks() + 1 entries; the last is the total).
  std::span<const std::uint64_t> send_counts() const { return send_counts_; }
  std::span<const std::uint64_t> recv_counts() const { return recv_counts_; }
  std::span<const std::uint64_t> send_offsets() const { return send_offsets_; }
  std::span<const std::uint64_t> recv_offsets() const { return recv_offsets_; }

  // Send item k (ordered by destination) is local item export_index()[k], for rank
  // export_rank()[k]; it was entry export_order()[k] of the list the plan was built from.
  std::span<const std::uint32_t> export_index() const { return export_index_; }
  std::span<const std::int32_t> export_rank() const { return export_rank_; }
  std::span<const std::uint32_t> export_order() const { return export_order_; }
  // Source rank of each received item.
  std::span<const std::int32_t> import_rank() const { return import_rank_; }

  // The same lists as variables, for kernels in any memory space.
  DiscreteVariable<std::uint32_t>& export_index_variable() const { return vars_->export_index; }
  DiscreteVariable<std::int32_t>& export_rank_variable() const { return vars_->export_rank; }
  DiscreteVariable<std::int32_t>& import_rank_variable() const { return vars_->import_rank; }
  DiscreteVariable<std::uint64_t>& send_offsets_variable() const { return vars_->send_offsets; }
  DiscreteVariable<std::uint64_t>& recv_offsets_variable() const { return vars_->recv_offsets; }

 private:
  struct Variables {
    DiscreteVariable<std::uint32_t> export_index{"Plan.ExportIndex"};
    DiscreteVariable<std::int32_t> export_rank{"Plan.ExportRank"};
    DiscreteVariable<std::int32_t> import_rank{"Plan.ImportRank"};
    DiscreteVariable<std::uint64_t> send_offsets{"Plan.SendOffsets"};
    DiscreteVariable<std::uint64_t> recv_offsets{"Plan.RecvOffsets"};
  };
  int ranks_ = 1;
  int rank_ = 0;
  Index import_count_ = 0;
  std::vector<std::uint64_t> send_counts_, recv_counts_, send_offsets_, recv_offsets_;
  std::vector<std::uint32_t> export_index_, export_order_;
  std::vector<std::int32_t> export_rank_, import_rank_;
  std::unique_ptr<Variables> vars_;
};

}  // namespace unisph::comm
