#pragma once
// Migration: owned particles whose owner (by the decomposition) is another rank move there,
// with every sortable variable of their registry (positions, velocities, ids, ...).
//
//   wrap_into_box(policy, grid, positions)      positions wrapped into the box along periodic axes
//   Plan plan = migration_plan(comm, decomposition, positions_on_host)   (collective)
//   Index owned = migrate(policy, transport, plan, registry, owned, exchange)   (collective)
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
}  // namespace migrate_detail

// Wraps positions into the box along the grid's periodic axes (by one period).
template <ExecutionPolicy P, int D>
void wrap_into_box(P policy, const CellGrid<D>& grid, DiscreteVariable<Vec<Real, D>>& positions, Index count) {
  particle_for(policy, count,
               migrate_detail::WrapIntoBox<D>{positions.read_write(policy), grid.box.lower, grid.period(),
                                              grid.periodic});
}

// Collective: the plan that sends every owned particle (positions[0, count) on the host) whose
// owner is another rank to its owner.
template <int D>
Plan migration_plan(const Communicator& comm, const Decomposition<D>& decomposition,
                    View<const Vec<Real, D>> positions) {
  if (decomposition.ranks() != comm.size())
    throw Error("migration: the decomposition is for " + std::to_string(decomposition.ranks()) + " ranks, the run has " +
                std::to_string(comm.size()));
  std::vector<std::uint32_t> index;
  std::vector<int> rank;
  for (Index i = 0; i < positions.size(); ++i) {
    const int owner = decomposition.owner(positions[i]);
    if (owner != comm.rank()) {
      index.push_back(static_cast<std::uint32_t>(i));
      rank.push_back(owner);
    }
  }
  return Plan(comm, index, rank);
}

// Collective: moves the exported particles of `plan` (built from owned particles of this
// registry) to their destinations and receives the arrivals. The registry must hold exactly
// `owned_count` particles (no ghosts). Returns the new owned count; the registry has that size.
template <ExecutionPolicy P>
Index migrate(P policy, Transport& transport, const Plan& plan, VariableRegistry& variables, Index owned_count,
              VariableExchange& exchange) {
  if (variables.size() != owned_count)
    throw Error("migrate: " + variables.owner() + " holds " + std::to_string(variables.size()) + " particles but " +
                std::to_string(owned_count) + " are owned; drop the ghosts before migrating");
  // The particles that stay, in order.
  std::vector<char> leaves(owned_count, 0);
  for (std::uint32_t i : plan.export_index()) {
    if (i >= owned_count)
      throw Error("migrate: the plan exports particle " + std::to_string(i) + " of " + std::to_string(owned_count));
    leaves[i] = 1;
  }
  std::vector<std::uint32_t> stay;
  stay.reserve(owned_count - plan.export_count());
  for (Index i = 0; i < owned_count; ++i)
    if (!leaves[i]) stay.push_back(static_cast<std::uint32_t>(i));
  if (stay.size() + plan.export_count() != owned_count)
    throw Error("migrate: the plan exports a particle more than once");
  const Index kept = stay.size();
  const Index new_count = kept + plan.import_count();

  std::vector<VariableBase*> travelling;
  variables.for_each([&](VariableRegistry::Entry& e) {
    if (e.flags.sortable) travelling.push_back(e.variable.get());
  });
  DiscreteVariable<std::uint32_t> stay_index("Migrate.Stay");
  stay_index.assign(stay);
  DiscreteVariable<std::uint32_t> scratch("Migrate.Scratch");

  exchange.run(
      policy, plan, transport, travelling, kept,
      [&] {
        // Compact the particles that stay to [0, kept), then make room for the arrivals.
        if (kept != owned_count) {
          View<const std::uint32_t> order = stay_index.read(policy);
          for (VariableBase* v : travelling) {
            const std::size_t bytes = kept * v->element_size();
            scratch.resize(std::max<Index>(scratch.size(), (bytes + 3) / 4));
            void* tmp = scratch.write(policy).data();
            void* data = v->prepare(P::space, Access::read_write);
            gather_by_permutation(policy, order, data, tmp, v->element_size());
            copy_bytes(policy, tmp, data, bytes);
          }
        }
        variables.resize(new_count);
      },
      [](auto&&...) { return false; });
  return new_count;
}

}  // namespace unisph::comm
