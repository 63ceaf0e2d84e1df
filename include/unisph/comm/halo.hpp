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
//   Halo<3> halo(comm, decomposition, positions_on_host, cutoff);          (collective)
//   halo.gather(policy, transport, set, "Position");            ghosts of every sortable variable
//   ... owned particles move or change ...
//   halo.refresh(policy, transport, set, "Position", {"Position", "Density"});   only these
//
// Ghosts arrive after the owned particles, by source rank, in each source's particle order;
// their positions carry the image shift. Build a new Halo after migrating.

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
template <int D, class S = Real>
class Halo {
 public:
  using Position = Vec<S, D>;
  using PlanPosition = Vec<Real, D>;

  Halo(const Communicator& comm, const Decomposition<D>& decomposition, View<const PlanPosition> positions, Real cutoff)
      : plan_(build(comm, decomposition, positions, cutoff)) {
    std::vector<Position> shifts(shifts_.size());
    for (std::size_t k = 0; k < shifts_.size(); ++k)
      for (int a = 0; a < D; ++a) shifts[k][a] = static_cast<S>(shifts_[k][a]);
    shift_.assign(shifts);
  }

  const Plan& plan() const { return plan_; }
  Index ghost_count() const { return plan_.import_count(); }
  // The image shift of each send item (in the plan's send order).
  std::span<const PlanPosition> shifts() const { return shifts_; }

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

 private:
  template <ExecutionPolicy P>
  void run(P policy, Transport& transport, VariableRegistry& variables, Index owned_count, std::string_view position,
           std::span<const std::string> names, bool resize) {
    std::vector<VariableBase*> list;
    if (names.empty()) {
      variables.for_each([&](VariableRegistry::Entry& e) {
        if (e.flags.sortable) list.push_back(e.variable.get());
      });
    } else {
      for (const std::string& n : names) list.push_back(variables.entry(n).variable.get());
    }
    VariableBase* pos = &variables.template get<Position>(position);  // checks the name and type
    if (variables.size() != (resize ? variables.size() : owned_count + ghost_count()))
      throw Error("halo: " + variables.owner() + " holds " + std::to_string(variables.size()) + " particles; " +
                  std::to_string(owned_count) + " owned and " + std::to_string(ghost_count()) +
                  " ghosts expected (gather before refresh)");
    if (plan_.export_count() && max_index_ >= owned_count)
      throw Error("halo: the plan sends particle " + std::to_string(max_index_) + " but " + variables.owner() +
                  " owns " + std::to_string(owned_count));
    exchange_.run(
        policy, plan_, transport, list, owned_count,
        [&] {
          if (resize) variables.resize(owned_count + ghost_count());
        },
        [&](std::size_t v, P, View<const std::uint32_t> index, View<const std::int32_t> rank,
            View<const std::uint64_t> items, View<const std::uint64_t> segment, const void* src,
            unsigned char* buffer) {
          if (list[v] != pos) return false;
          particle_for(policy, plan_.export_count(),
                       exchange_detail::PackShifted<Position>{index, rank, items, segment, shift_.read(policy),
                                                              static_cast<const Position*>(src), buffer});
          return true;
        });
  }

  Plan build(const Communicator& comm, const Decomposition<D>& d, View<const PlanPosition> positions, Real cutoff) {
    const CellGrid<D>& g = d.grid();
    if (d.ranks() != comm.size())
      throw Error("halo: the decomposition is for " + std::to_string(d.ranks()) + " ranks, the run has " +
                  std::to_string(comm.size()));
    for (int a = 0; a < D; ++a)
      if (g.cell_size[a] < cutoff)
        throw Error("halo: cells " + std::to_string(g.cell_size[a]) + " wide along axis " + std::to_string(a) +
                    " are narrower than the cutoff " + std::to_string(cutoff) + " (make_cell_grid(box, cutoff))");
    const Real cutoff2 = cutoff * cutoff;
    const PlanPosition period = g.period();
    std::vector<std::uint32_t> index;
    std::vector<int> rank;
    std::vector<PlanPosition> shift;
    int offsets = 1;
    for (int a = 0; a < D; ++a) offsets *= 3;
    struct Target {
      int rank;
      Vec<int, D> image;
    };
    std::vector<Target> targets;
    for (Index i = 0; i < positions.size(); ++i) {
      const PlanPosition x = positions[i];
      const Vec<int, D> c = g.cell_of(x);
      if (d.interior(c)) continue;  // every cell within reach is this rank's own
      targets.clear();
      for (int o = 0; o < offsets; ++o) {
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
        PlanPosition y = x;
        bool zero = true;
        for (int a = 0; a < D; ++a) {
          y[a] += static_cast<Real>(image[a]) * period[a];
          zero = zero && image[a] == 0;
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
        const int r = d.owner_of_cell(n);
        if (r == comm.rank() && zero) continue;
        bool seen = false;
        for (const Target& t : targets)
          if (t.rank == r && same(t.image, image)) seen = true;
        if (seen) continue;
        targets.push_back({r, image});
        index.push_back(static_cast<std::uint32_t>(i));
        rank.push_back(r);
        PlanPosition s{};
        for (int a = 0; a < D; ++a) s[a] = static_cast<Real>(image[a]) * period[a];
        shift.push_back(s);
        max_index_ = i;
      }
    }
    Plan plan(comm, index, rank);
    shifts_.resize(shift.size());
    for (Index k = 0; k < shift.size(); ++k) shifts_[k] = shift[plan.export_order()[k]];
    return plan;
  }

  static bool same(const Vec<int, D>& a, const Vec<int, D>& b) {
    for (int k = 0; k < D; ++k)
      if (a[k] != b[k]) return false;
    return true;
  }

  Index max_index_ = 0;
  std::vector<PlanPosition> shifts_;
  Plan plan_;
  DiscreteVariable<Position> shift_{"Halo.Shift"};
  VariableExchange exchange_;
};

}  // namespace unisph::comm
