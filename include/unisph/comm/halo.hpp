#pragma once
// Halo: ghost copies of the owned particles within the cutoff of another rank's subdomain
// (Cabana's Halo, AMReX's fill-neighbours).
//
// A particle gives a ghost to rank r with image shift s (s is 0, or +-period along periodic
// axes) when its position shifted by s lies within `cutoff` of a cell that r owns, except
// r == this rank with s == 0 (the particle itself). Each (particle, r, s) once: a particle at a
// subdomain corner goes once to each rank around the corner, and once more per periodic image
// a rank needs. Cells are at least `cutoff` wide, so the cells within the cutoff of a
// particle are among its cell's 3^D neighbours; the edge cells along non-periodic axes extend
// outward without end (as ownership does). Positions must lie in the box along periodic axes
// (wrap_into_box).
//
//   Halo<3> halo(policy, comm, decomposition, positions, cutoff);   (collective; kernels)
//   halo.gather(policy, transport, set, "Position");            ghosts of every sortable variable
//   ... owned particles move or change ...
//   halo.refresh(policy, transport, set, "Position", {"Position", "Density"});   only these
//   halo.refresh_begin(policy, transport, set, "Position", names);  the same in two halves,
//   ... work that reads no ghost ...                                around work on interior
//   halo.refresh_end(policy, set);                                  particles (interior_split.hpp)
//   halo.build(policy, comm, decomposition, positions, cutoff);     the next step's, same storage
//
// Ghosts arrive after the owned particles, by source rank, in each source's particle order;
// their positions carry the image shift. Build the halo again after migrating.
//
// The plan is built where the positions are, by kernels: each particle counts its (rank,
// image) targets, an exclusive scan places them, a second pass writes them, and a stable radix
// sort by rank orders them as the plan wants (by rank, then by particle, then by target);
// only the counts per rank reach the host. Halo(comm, decomposition, positions_on_host,
// cutoff) runs the same kernels on the host's sequential policy.

#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "unisph/comm/decomposition.hpp"
#include "unisph/comm/exchange.hpp"
#include "unisph/comm/plan.hpp"
#include "unisph/particles/particle_set.hpp"
#include "unisph/particles/variable_registry.hpp"

namespace unisph::comm {

// S: the scalar of the position variable that gather() shifts (a solver in float under a
// double build); the plan is built from positions in Real.
namespace halo_detail {
// The (rank, image) targets of particle i (see the header comment), each once: counted
// (offsets empty) or written from offsets[i] on: key = rank, item = its place, source = i,
// shift = the image's displacement.
template <int D, class PS, class S>
struct HaloTargets {
  DecompositionView<D> decomposition;
  View<const Vec<PS, D>> positions;
  Real cutoff2;
  int me;
  View<std::uint32_t> counts;
  View<const std::uint32_t> offsets;
  View<std::uint32_t> key, item, source;
  View<Vec<S, D>> shift;

  UNISPH_HOST_DEVICE void operator()(Index i) const {
    constexpr int offsets_per_cell = D == 2 ? 9 : 27;
    const CellGrid<D>& g = decomposition.grid;
    Vec<Real, D> x;
    for (int a = 0; a < D; ++a) x[a] = static_cast<Real>(positions[i][a]);
    const Vec<int, D> c = g.cell_of(x);
    std::uint32_t found = 0;
    if (!decomposition.is_interior(c)) {  // else every cell within reach is this rank's own
      int target_rank[offsets_per_cell];
      int target_image[offsets_per_cell];  // the image's code in base 3
      const Vec<Real, D> period = g.period();
      for (int o = 0; o < offsets_per_cell; ++o) {
        Vec<int, D> n{};
        Vec<int, D> image{};  // -1, 0, +1 periods
        bool inside = true;
        for (int a = 0, code = o; a < D; ++a, code /= 3) {
          n[a] = c[a] + code % 3 - 1;
          if (n[a] < 0 || n[a] >= g.cells[a]) {
            if (!g.periodic[a]) {
              inside = false;
              break;
            }
            image[a] = n[a] < 0 ? 1 : -1;  // the neighbour across the lower face sees x one period up
            n[a] += n[a] < 0 ? g.cells[a] : -g.cells[a];
          }
        }
        if (!inside) continue;
        Vec<Real, D> y = x;
        bool zero = true;
        int code = 0;
        for (int a = D - 1; a >= 0; --a) {
          y[a] += static_cast<Real>(image[a]) * period[a];
          zero = zero && image[a] == 0;
          code = code * 3 + image[a] + 1;
        }
        // Distance from y to the cell n (edge cells open outward along non-periodic axes).
        Real d2 = 0;
        for (int a = 0; a < D; ++a) {
          const Real lo = g.box.lower[a] + static_cast<Real>(n[a]) * g.cell_size[a];
          const Real hi = n[a] + 1 == g.cells[a] ? g.box.upper[a] : lo + g.cell_size[a];
          const bool open_lo = !g.periodic[a] && n[a] == 0, open_hi = !g.periodic[a] && n[a] + 1 == g.cells[a];
          Real gap = 0;
          if (y[a] < lo && !open_lo) gap = lo - y[a];
          if (y[a] > hi && !open_hi) gap = y[a] - hi;
          d2 += gap * gap;
        }
        if (d2 > cutoff2) continue;
        const int r = decomposition.owner_of_cell(n);
        if (r == me && zero) continue;
        bool seen = false;
        for (std::uint32_t t = 0; t < found; ++t)
          if (target_rank[t] == r && target_image[t] == code) seen = true;
        if (seen) continue;
        target_rank[found] = r;
        target_image[found] = code;
        if (!offsets.empty()) {
          const std::uint32_t at = offsets[i] + found;
          key[at] = static_cast<std::uint32_t>(r);
          item[at] = at;
          source[at] = static_cast<std::uint32_t>(i);
          Vec<S, D> s{};
          for (int a = 0; a < D; ++a) s[a] = static_cast<S>(static_cast<Real>(image[a]) * period[a]);
          shift[at] = s;
        }
        ++found;
      }
    }
    if (offsets.empty()) counts[i] = found;
  }
};

// Send item k of the plan: the item at place item[k] after the sort by rank.
template <int D, class S>
struct OrderSendItems {
  View<const std::uint32_t> key, item, source;
  View<const Vec<S, D>> slot_shift;
  View<std::uint32_t> index;
  View<std::int32_t> rank;
  View<Vec<S, D>> shift;
  UNISPH_HOST_DEVICE void operator()(Index k) const {
    index[k] = source[item[k]];
    rank[k] = static_cast<std::int32_t>(key[k]);
    shift[k] = slot_shift[item[k]];
  }
};
}  // namespace halo_detail

template <int D, class S = Real>
class Halo {
 public:
  using Position = Vec<S, D>;
  using PlanPosition = Vec<Real, D>;

  // Collective. `positions`: the owned particles' positions in the policy's memory (float or
  // double).
  // `scratch`: the storage of the plan-building kernels, which the caller may share among halos
  // and migrations built one after another (it is not needed between builds); null: the
  // halo's own.
  template <ExecutionPolicy P, class PS>
  Halo(P policy, const Communicator& comm, const Decomposition<D>& decomposition, View<const Vec<PS, D>> positions,
       Real cutoff, PlanScratch* scratch = nullptr)
      : shared_(scratch), plan_(build_plan(policy, comm, decomposition, positions, cutoff)) {}
  // The same from positions on the host.
  Halo(const Communicator& comm, const Decomposition<D>& decomposition, View<const PlanPosition> positions, Real cutoff)
      : Halo(SequencedPolicy{}, comm, decomposition, positions, cutoff) {}

  // Collective: the plan anew for the current owned positions, reusing this halo's storage.
  template <ExecutionPolicy P, class PS>
  void build(P policy, const Communicator& comm, const Decomposition<D>& decomposition,
             View<const Vec<PS, D>> positions, Real cutoff) {
    plan_ = build_plan(policy, comm, decomposition, positions, cutoff, &plan_);
  }

  const Plan& plan() const { return plan_; }
  Index ghost_count() const { return plan_.import_count(); }
  // The image shift of each send item (in the plan's send order), on the host.
  std::vector<Position> shifts() {
    std::vector<Position> all = shift_.to_vector();
    all.resize(plan_.export_count());
    return all;
  }

  // Resizes the registry to owned_count + ghost_count() and fills the ghosts of the named
  // variables (none named: every sortable variable). `position` names the position variable
  // (a Vec<Real, D>), whose copies are shifted by their image.
  template <ExecutionPolicy P>
  void gather(P policy, Transport& transport, VariableRegistry& variables, Index owned_count, std::string_view position,
              std::span<const std::string> names = {}) {
    run(policy, transport, variables, owned_count, position, names, true);
  }
  template <ExecutionPolicy P>
  void gather(P policy, Transport& transport, ParticleSet& set, std::string_view position,
              std::span<const std::string> names = {}) {
    set.set_ghost_count(ghost_count());
    run(policy, transport, set.variables(), set.owned_count(), position, names, false);
  }
  // Sends the named variables again along the same plan (the ghosts must be there already).
  template <ExecutionPolicy P>
  void refresh(P policy, Transport& transport, VariableRegistry& variables, Index owned_count,
               std::string_view position, std::span<const std::string> names) {
    run(policy, transport, variables, owned_count, position, names, false);
  }
  template <ExecutionPolicy P>
  void refresh(P policy, Transport& transport, ParticleSet& set, std::string_view position,
               std::span<const std::string> names) {
    run(policy, transport, set.variables(), set.owned_count(), position, names, false);
  }
  // The refresh in two halves, around work that reads no ghost and writes none of the named
  // variables (the interior particles' interactions): refresh_begin() packs and starts the
  // exchange (Transport::begin), refresh_end() completes it and fills the ghosts. Nothing else
  // may use this halo, or exchange through the transport, in between.
  template <ExecutionPolicy P>
  void refresh_begin(P policy, Transport& transport, VariableRegistry& variables, Index owned_count,
                     std::string_view position, std::span<const std::string> names) {
    select(variables, owned_count, position, names, false);
    exchange_.start(policy, plan_, transport, std::span<VariableBase* const>(selected_), pack_shifted(policy), true);
  }
  template <ExecutionPolicy P>
  void refresh_end(P policy, Index owned_count) {
    exchange_.complete(policy, plan_, std::span<VariableBase* const>(selected_), owned_count);
  }
  template <ExecutionPolicy P>
  void refresh_begin(P policy, Transport& transport, ParticleSet& set, std::string_view position,
                     std::span<const std::string> names) {
    refresh_begin(policy, transport, set.variables(), set.owned_count(), position, names);
  }
  template <ExecutionPolicy P>
  void refresh_end(P policy, ParticleSet& set) {
    refresh_end(policy, set.owned_count());
  }

 private:
  // The variables to send (none named: every sortable one), with the checks a refresh needs.
  void select(VariableRegistry& variables, Index owned_count, std::string_view position,
              std::span<const std::string> names, bool resize) {
    selected_.clear();
    if (names.empty()) {
      variables.for_each([&](VariableRegistry::Entry& e) {
        if (e.flags.sortable) selected_.push_back(e.variable.get());
      });
    } else {
      for (const std::string& n : names) selected_.push_back(variables.entry(n).variable.get());
    }
    position_ = &variables.template get<Position>(position);  // checks the name and type
    if (variables.size() != (resize ? variables.size() : owned_count + ghost_count()))
      throw Error("halo: " + variables.owner() + " holds " + std::to_string(variables.size()) + " particles; " +
                  std::to_string(owned_count) + " owned and " + std::to_string(ghost_count()) +
                  " ghosts expected (gather before refresh)");
    if (plan_.export_count() && source_count_ > owned_count)
      throw Error("halo: the plan was built for " + std::to_string(source_count_) + " particles but " +
                  variables.owner() + " owns " + std::to_string(owned_count));
  }
  // Packs the position variable shifted by each item's image; the others as they are.
  template <ExecutionPolicy P>
  auto pack_shifted(P policy) {
    return [this, policy](std::size_t v, P, View<const std::uint32_t> index, View<const std::int32_t> rank,
                          View<const std::uint64_t> items, View<const std::uint64_t> segment, const void* src,
                          unsigned char* buffer) {
      if (selected_[v] != position_) return false;
      particle_for(policy, plan_.export_count(),
                   exchange_detail::PackShifted<Position>{index, rank, items, segment, shift_.read(policy),
                                                          static_cast<const Position*>(src), buffer});
      return true;
    };
  }
  template <ExecutionPolicy P>
  void run(P policy, Transport& transport, VariableRegistry& variables, Index owned_count, std::string_view position,
           std::span<const std::string> names, bool resize) {
    select(variables, owned_count, position, names, resize);
    exchange_.run(
        policy, plan_, transport, std::span<VariableBase* const>(selected_), owned_count,
        [&] {
          if (resize) variables.resize(owned_count + ghost_count());
        },
        pack_shifted(policy));
  }

  template <ExecutionPolicy P, class PS>
  Plan build_plan(P policy, const Communicator& comm, const Decomposition<D>& d, View<const Vec<PS, D>> positions,
                  Real cutoff, Plan* previous = nullptr) {
    const CellGrid<D>& g = d.grid();
    if (d.ranks() != comm.size())
      throw Error("halo: the decomposition is for " + std::to_string(d.ranks()) + " ranks, the run has " +
                  std::to_string(comm.size()));
    for (int a = 0; a < D; ++a)
      if (g.cell_size[a] < cutoff)
        throw Error("halo: cells " + std::to_string(g.cell_size[a]) + " wide along axis " + std::to_string(a) +
                    " are narrower than the cutoff " + std::to_string(cutoff) + " (make_cell_grid(box, cutoff))");
    const Index n = positions.size();
    source_count_ = n;
    const DecompositionView<D> view = d.view(policy);
    // Count, place, write; every array but the plan's and the shifts lives only within the build.
    WorkspaceScope scope(policy);
    halo_detail::HaloTargets<D, PS, S> targets{view, positions, cutoff * cutoff, comm.rank(),
                                                scope.take(policy, work().counts, n), {}, {}, {}, {}, {}};
    particle_for(policy, n, targets);
    const View<std::uint32_t> offsets = scope.take(policy, work().offsets, n + 1);
    exclusive_scan(policy, View<const std::uint32_t>(targets.counts), offsets);
    const Index items = work().element(policy, View<const std::uint32_t>(offsets), n);
    targets.offsets = offsets;
    targets.key = scope.take(policy, work().keys, items);
    targets.item = scope.take(policy, work().values, items);
    targets.source = scope.take(policy, source_, items);
    targets.shift = scope.take(policy, slot_shift_, items);
    particle_for(policy, n, targets);
    // By rank, stably.
    const int p = comm.size();
    int bits = 1;
    while ((1 << bits) < p) ++bits;
    sort_pairs(policy, targets.key, targets.item, 0, bits);
    const std::vector<std::uint64_t> starts = work().bin_starts(policy, View<const std::uint32_t>(targets.key), Index(p));
    std::vector<std::uint64_t> counts(std::size_t(p), 0);
    for (int r = 0; r < p; ++r)
      counts[std::size_t(r)] = starts[std::size_t(r) + 1] - starts[std::size_t(r)];
    const View<Position> shift = PlanScratch::room(policy, shift_, items);
    return Plan::from_ordered(
        policy, comm, counts,
        [&](View<std::uint32_t> index, View<std::int32_t> rank) {
          particle_for(policy, items,
                       halo_detail::OrderSendItems<D, S>{targets.key, targets.item, targets.source, targets.shift,
                                                         index, rank, shift});
        },
        previous);
  }

  PlanScratch& work() { return shared_ ? *shared_ : own_; }

  // Before plan_: build_plan fills them while plan_ is made.
  PlanScratch* shared_ = nullptr;
  Index source_count_ = 0;
  PlanScratch own_;
  DiscreteVariable<std::uint32_t> source_{"Halo.Source"};
  DiscreteVariable<Position> slot_shift_{"Halo.SlotShift"};
  DiscreteVariable<Position> shift_{"Halo.Shift"};  // per send item
  Plan plan_;
  VariableExchange exchange_;
  std::vector<VariableBase*> selected_;  // what the last refresh or gather sends
  VariableBase* position_ = nullptr;
};

}  // namespace unisph::comm
