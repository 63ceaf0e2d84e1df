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
// The plan keeps its lists as variables readable in any memory space (for the packing
// kernels). A plan built on the host from lists also keeps them on the host; one built by
// kernels (Plan::from_ordered: the migration and halo plans of a run) copies them to the host
// only where asked (export_index() and the other spans).

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "unisph/comm/communicator.hpp"
#include "unisph/core/partition_point.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/exec/workspace.hpp"
#include "unisph/memory/discrete_variable.hpp"

namespace unisph::comm {

namespace plan_detail {
// The source rank of received item j, from the receive offsets (ranks + 1).
struct FillSourceRanks {
  View<const std::uint64_t> offsets;
  View<std::int32_t> rank;
  UNISPH_HOST_DEVICE void operator()(Index j) const {
    int r = 0;
    while (std::uint64_t(j) >= offsets[Index(r) + 1]) ++r;
    rank[j] = r;
  }
};
struct CopyElement {
  View<const std::uint32_t> from;
  Index at;
  View<std::uint32_t> to;
  UNISPH_HOST_DEVICE void operator()(Index) const { to[0] = from[at]; }
};

// first[b] for b in [0, bins]: the first place of the sorted keys that is >= b (a lower bound),
// so that bin b holds the places [first[b], first[b + 1]).
struct BinStarts {
  View<const std::uint32_t> keys;
  View<std::uint64_t> first;
  UNISPH_HOST_DEVICE void operator()(Index b) const {
    first[b] = partition_point(Index(0), keys.size(), [&](Index k) { return keys[k] < std::uint32_t(b); });
  }
};
}  // namespace plan_detail

// Reusable storage of the kernels that build plans, so that a plan built every step allocates
// nothing once the sizes settle. keys, values, counts and offsets live only while a plan is built
// or a migration runs: they are taken in a WorkspaceScope (exec/workspace.hpp), and these
// variables are their storage on the host; on the device the workspace holds them.
struct PlanScratch {
  DiscreteVariable<std::uint32_t> keys{"Plan.Keys"};
  DiscreteVariable<std::uint32_t> values{"Plan.Values"};
  DiscreteVariable<std::uint32_t> counts{"Plan.Counts"};
  DiscreteVariable<std::uint32_t> offsets{"Plan.Offsets"};
  DiscreteVariable<std::uint64_t> starts{"Plan.BinStarts"};
  DiscreteVariable<std::uint32_t> bytes{"Plan.Bytes"};  // a variable being compacted, on the host (permute_in_place)
  DiscreteVariable<std::uint32_t> one{"Plan.One", 1};
  // Grows `v` to at least n elements (never shrinks) and returns the first n.
  template <class P, class T>
  static View<T> room(P policy, DiscreteVariable<T>& v, Index n) {
    if (v.size() < n) v.resize(n + n / 8 + 64);
    return v.read_write(policy).subview(0, n);
  }
  // view[i] on the host (one element copied, not the view).
  template <class P>
  std::uint32_t element(P policy, View<const std::uint32_t> view, Index i) {
    particle_for(policy, 1, plan_detail::CopyElement{view, i, one.write(policy)});
    return one.to_vector()[0];
  }
  // The starts of `bins` bins of keys sorted ascending (bins + 1 values, on the host).
  template <class P>
  std::vector<std::uint64_t> bin_starts(P policy, View<const std::uint32_t> sorted, Index bins) {
    starts.resize(bins + 1);
    particle_for(policy, bins + 1, plan_detail::BinStarts{sorted, starts.write(policy)});
    return starts.to_vector();
  }
};

class Plan {
 public:
  // Collective. export_rank[k] in [0, comm.size()) is the destination of local item
  // export_index[k].
  Plan(const Communicator& comm, std::span<const std::uint32_t> export_index, std::span<const int> export_rank);

  // Collective. A plan whose send items a kernel lists, already ordered by destination:
  // send_counts[r] items for rank r, in rank order; fill(index, rank) writes the local index
  // and the destination of each in the policy's memory space. Nothing passes through the host
  // but the counts. `reuse`: a plan no longer needed (it is left empty) whose lists the new one
  // takes over, keeping their allocations where the sizes fit; without it a plan rebuilt every
  // step allocates its lists anew each time and frees the old ones (cudaFree waits for the
  // device).
  template <ExecutionPolicy P, class Fill>
  static Plan from_ordered(P policy, const Communicator& comm, std::span<const std::uint64_t> send_counts,
                           Fill&& fill, Plan* reuse = nullptr) {
    Plan plan(comm);
    if (reuse && reuse->vars_) plan.vars_ = std::move(reuse->vars_);
    plan.set_send_counts(comm, send_counts);
    const Index n = plan.send_offsets_.back();
    plan.vars_->export_index.resize(n);
    plan.vars_->export_rank.resize(n);
    fill(plan.vars_->export_index.write(policy), plan.vars_->export_rank.write(policy));
    plan.receive_counts(comm);
    plan.vars_->import_rank.resize(plan.import_count_);
    particle_for(policy, plan.import_count_,
                 plan_detail::FillSourceRanks{plan.vars_->recv_offsets.read(policy),
                                              plan.vars_->import_rank.write(policy)});
    plan.export_count_ = n;
    plan.host_lists_ = false;
    return plan;
  }

  int ranks() const { return ranks_; }
  int rank() const { return rank_; }
  Index export_count() const { return export_count_; }
  Index import_count() const { return import_count_; }

  // Items per rank and their exclusive scans (ranks() + 1 entries; the last is the total).
  std::span<const std::uint64_t> send_counts() const { return send_counts_; }
  std::span<const std::uint64_t> recv_counts() const { return recv_counts_; }
  std::span<const std::uint64_t> send_offsets() const { return send_offsets_; }
  std::span<const std::uint64_t> recv_offsets() const { return recv_offsets_; }

  // Send item k (ordered by destination) is local item export_index()[k], for rank
  // export_rank()[k]; it was entry export_order()[k] of the list the plan was built from
  // (empty for a plan from_ordered). Copied from the variables on first use where a kernel
  // built the plan.
  std::span<const std::uint32_t> export_index() const {
    copy_lists_to_host();
    return export_index_;
  }
  std::span<const std::int32_t> export_rank() const {
    copy_lists_to_host();
    return export_rank_;
  }
  std::span<const std::uint32_t> export_order() const { return export_order_; }
  // Source rank of each received item.
  std::span<const std::int32_t> import_rank() const {
    copy_lists_to_host();
    return import_rank_;
  }

  // The same lists as variables, for kernels in any memory space.
  DiscreteVariable<std::uint32_t>& export_index_variable() const { return vars_->export_index; }
  DiscreteVariable<std::int32_t>& export_rank_variable() const { return vars_->export_rank; }
  DiscreteVariable<std::int32_t>& import_rank_variable() const { return vars_->import_rank; }
  DiscreteVariable<std::uint64_t>& send_offsets_variable() const { return vars_->send_offsets; }
  DiscreteVariable<std::uint64_t>& recv_offsets_variable() const { return vars_->recv_offsets; }

 private:
  explicit Plan(const Communicator& comm);
  void set_send_counts(const Communicator& comm, std::span<const std::uint64_t> send_counts);
  void receive_counts(const Communicator& comm);  // recv counts, offsets and the offsets' variables
  void copy_lists_to_host() const;

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
  Index export_count_ = 0;
  std::vector<std::uint64_t> send_counts_, recv_counts_, send_offsets_, recv_offsets_;
  mutable bool host_lists_ = true;  // export_index_, export_rank_ and import_rank_ are current
  mutable std::vector<std::uint32_t> export_index_;
  std::vector<std::uint32_t> export_order_;
  mutable std::vector<std::int32_t> export_rank_, import_rank_;
  std::unique_ptr<Variables> vars_;
};

}  // namespace unisph::comm
