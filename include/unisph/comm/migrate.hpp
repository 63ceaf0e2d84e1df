#pragma once
// Migration: owned particles whose owner (by the decomposition) is another rank move there,
// with every sortable variable of their registry (positions, velocities, ids, ...).
//
//   wrap_into_box(policy, grid, positions)      positions wrapped into the box along periodic axes
//   Plan plan = migration_plan(policy, comm, decomposition, positions)   (collective; kernels)
//   Index owned = migrate(policy, transport, plan, registry, owned, exchange)   (collective)
//
// The plan is built where the positions are: each particle's owner by a kernel, a stable radix
// sort of (destination, index) and the counts per destination from the sorted keys; only the
// counts reach the host (migration_plan(comm, decomposition, positions) runs the same kernels
// on the host's sequential policy).
//
// After migrate the registry holds the particles that stayed, in their old order, then the
// arrivals, by source rank and in each source's order; it has no ghosts (build the halo after
// migrating). Variables that are not sortable are scratch: they are resized, their contents
// are not moved.
//
// ParticleSet cannot take part yet: its owned count is fixed at construction (there is no way
// to change it, nor to rebuild index_of_id() for ids that are not first_id + k), so migrate
// works on the registry and the owned count (docs/multi_gpu.md).

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "unisph/comm/decomposition.hpp"
#include "unisph/comm/exchange.hpp"
#include "unisph/comm/plan.hpp"
#include "unisph/particles/permute_bytes.hpp"
#include "unisph/particles/variable_registry.hpp"

namespace unisph::comm {

namespace migrate_detail {
template <int D>
struct WrapIntoBox {
  View<Vec<Real, D>> position;
  Vec<Real, D> lower, period;
  Vec<int, D> periodic;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    Vec<Real, D> x = position[i];
    for (int a = 0; a < D; ++a) {
      if (!periodic[a]) continue;
      // One period either way covers a particle that moved less than a box length in a step;
      // anything further is left alone (the owner function still wraps it).
      if (x[a] < lower[a]) x[a] += period[a];
      else if (x[a] >= lower[a] + period[a]) x[a] -= period[a];
    }
    position[i] = x;
  }
};
// Key: the destination rank of particle i, or `ranks` where it stays (so that the particles
// that stay sort last, in their order); value: i.
template <int D, class S>
struct DestinationKeys {
  DecompositionView<D> decomposition;
  View<const Vec<S, D>> positions;
  int me;
  View<std::uint32_t> key;
  View<std::uint32_t> value;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    Vec<Real, D> x;
    for (int a = 0; a < D; ++a) x[a] = static_cast<Real>(positions[i][a]);
    const int owner = decomposition.owner(x);
    key[i] = static_cast<std::uint32_t>(owner == me ? decomposition.ranks : owner);
    value[i] = static_cast<std::uint32_t>(i);
  }
};

struct CopySendItems {
  View<const std::uint32_t> sorted_index;
  View<const std::uint32_t> sorted_rank;
  View<std::uint32_t> index;
  View<std::int32_t> rank;
  UNISPH_HOST_DEVICE void operator()(Index k) const {
    index[k] = sorted_index[k];
    rank[k] = static_cast<std::int32_t>(sorted_rank[k]);
  }
};

// stays[i] = 1 for every particle, then 0 for each exported one (marks[i] counts its exports).
struct ClearLeaving {
  View<std::uint32_t> stays;
  UNISPH_HOST_DEVICE void operator()(Index i) const { stays[i] = 1; }
};
struct MarkLeaving {
  View<const std::uint32_t> index;
  View<std::uint32_t> stays;
  UNISPH_HOST_DEVICE void operator()(Index k) const { stays[index[k]] = 0; }
};
// Compacts the particles that stay: place[i] is the exclusive scan of stays.
struct ListStaying {
  View<const std::uint32_t> stays;
  View<const std::uint32_t> place;
  View<std::uint32_t> stay;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    if (stays[i]) stay[place[i]] = static_cast<std::uint32_t>(i);
  }
};
}  // namespace migrate_detail

// Wraps positions into the box along the grid's periodic axes (by one period).
template <ExecutionPolicy P, int D>
void wrap_into_box(P policy, const CellGrid<D>& grid, DiscreteVariable<Vec<Real, D>>& positions, Index count) {
  particle_for(policy, count,
               migrate_detail::WrapIntoBox<D>{positions.read_write(policy), grid.box.lower, grid.period(),
                                              grid.periodic});
}

// Collective: the plan that sends every owned particle (positions[0, count) in the policy's
// memory, float or double) whose owner is another rank to its owner, ordered by destination and
// within one destination by index. `previous`: the last migration's plan, whose lists this one
// takes over (Plan::from_ordered).
template <ExecutionPolicy P, int D, class S>
Plan migration_plan(P policy, const Communicator& comm, const Decomposition<D>& decomposition,
                    View<const Vec<S, D>> positions, PlanScratch& scratch, Plan* previous = nullptr) {
  if (decomposition.ranks() != comm.size())
    throw Error("migration: the decomposition is for " + std::to_string(decomposition.ranks()) + " ranks, the run has " +
                std::to_string(comm.size()));
  const Index n = positions.size();
  const int p = comm.size();
  WorkspaceScope scope(policy);  // the keys and values live only while the plan is built
  const View<std::uint32_t> keys = scope.take(policy, scratch.keys, n);
  const View<std::uint32_t> values = scope.take(policy, scratch.values, n);
  particle_for(policy, n,
               migrate_detail::DestinationKeys<D, S>{decomposition.view(policy), positions, comm.rank(), keys, values});
  int bits = 1;
  while ((1 << bits) <= p) ++bits;
  sort_pairs(policy, keys, values, 0, bits);
  const std::vector<std::uint64_t> starts = scratch.bin_starts(policy, View<const std::uint32_t>(keys), Index(p) + 1);
  std::vector<std::uint64_t> counts(std::size_t(p), 0);
  for (int r = 0; r < p; ++r) counts[std::size_t(r)] = starts[std::size_t(r) + 1] - starts[std::size_t(r)];
  return Plan::from_ordered(
      policy, comm, counts,
      [&](View<std::uint32_t> index, View<std::int32_t> rank) {
        particle_for(policy, index.size(), migrate_detail::CopySendItems{values, keys, index, rank});
      },
      previous);
}
template <ExecutionPolicy P, int D, class S>
Plan migration_plan(P policy, const Communicator& comm, const Decomposition<D>& decomposition,
                    View<const Vec<S, D>> positions) {
  PlanScratch scratch;
  return migration_plan(policy, comm, decomposition, positions, scratch);
}
// The same from positions on the host.
template <int D>
Plan migration_plan(const Communicator& comm, const Decomposition<D>& decomposition,
                    View<const Vec<Real, D>> positions) {
  return migration_plan(SequencedPolicy{}, comm, decomposition, positions);
}

// Collective: moves the exported particles of `plan` (built from owned particles of this
// registry) to their destinations and receives the arrivals. The registry must hold exactly
// `owned_count` particles (no ghosts). Returns the new owned count; the registry has that size.
template <ExecutionPolicy P>
Index migrate(P policy, Transport& transport, const Plan& plan, VariableRegistry& variables, Index owned_count,
              VariableExchange& exchange, PlanScratch& work) {
  if (variables.size() != owned_count)
    throw Error("migrate: " + variables.owner() + " holds " + std::to_string(variables.size()) + " particles but " +
                std::to_string(owned_count) + " are owned; drop the ghosts before migrating");
  // The particles that stay, in order: marked, scanned and compacted by kernels.
  WorkspaceScope scope(policy);
  const View<std::uint32_t> stays = scope.take(policy, work.counts, owned_count);
  const View<std::uint32_t> place = scope.take(policy, work.offsets, owned_count + 1);
  particle_for(policy, owned_count, migrate_detail::ClearLeaving{stays});
  particle_for(policy, plan.export_count(),
               migrate_detail::MarkLeaving{plan.export_index_variable().read(policy), stays});
  exclusive_scan(policy, View<const std::uint32_t>(stays), place);
  const Index kept = work.element(policy, View<const std::uint32_t>(place), owned_count);  // the scan's total
  if (kept + plan.export_count() != owned_count)
    throw Error("migrate: the plan exports " + std::to_string(plan.export_count()) + " items but " +
                std::to_string(owned_count - kept) + " particles leave: it exports a particle more than once");
  const View<std::uint32_t> stay_index = scope.take(policy, work.keys, kept);
  particle_for(policy, owned_count, migrate_detail::ListStaying{stays, place, stay_index});
  const Index new_count = kept + plan.import_count();

  std::vector<VariableBase*> travelling;
  variables.for_each([&](VariableRegistry::Entry& e) {
    if (e.flags.sortable) travelling.push_back(e.variable.get());
  });
  exchange.run(
      policy, plan, transport, travelling, kept,
      [&] {
        // Compact the particles that stay to [0, kept), then make room for the arrivals.
        if (kept != owned_count) {
          const View<const std::uint32_t> order(stay_index);
          for (VariableBase* v : travelling)
            permute_in_place(policy, order, v->prepare(P::space, Access::read_write), v->element_size(), work.bytes,
                             "migration's compaction");
        }
        variables.resize(new_count);
      },
      [](auto&&...) { return false; });
  return new_count;
}

template <ExecutionPolicy P>
Index migrate(P policy, Transport& transport, const Plan& plan, VariableRegistry& variables, Index owned_count,
              VariableExchange& exchange) {
  PlanScratch work;
  return migrate(policy, transport, plan, variables, owned_count, exchange, work);
}

}  // namespace unisph::comm
