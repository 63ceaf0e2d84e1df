#pragma once
// The neighbour records of a fluid body (PositionVolume, VelocityPressure: fluid_variables.hpp),
// what the pressure and density relaxations read of a fluid neighbour j:
//
//   PositionVolume<T, D>    {x_j, V_j = m_j / rho_j}  read for every candidate of a direct search
//   VelocityPressure<T, D>  {v_j, p_j}               read for every neighbour within the cutoff
//
// and here their writer, the walk over the fluid neighbours that reads them, and their refresh.
//
// Without them a GPU pair loads x_j as three 4-byte words per candidate and v_j, p_j, m_j,
// rho_j as six more per neighbour, and divides m_j by rho_j pair by pair; with them (float,
// 3D) one 16-byte load per candidate and one per neighbour, no division. The records are
// derived: written by the per-particle kernels that change their inputs (PressureRelaxationStart:
// x, rho, p; VelocityUpdate: x, v) and by RefreshNeighborRecords after a sort or a restore,
// never sorted or stored in a checkpoint. V_j = m_j / rho_j once per particle changes the
// relaxations' dW m_j / rho_j to dW (m_j / rho_j): the same physics, other last bits.
#include <cstdint>
#include <type_traits>

#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/neighbor/neighbor_search.hpp"
#include "unisph/sph/fluid_variables.hpp"

namespace unisph::sph {

// How a pair loop holds the {v_j, p_j} record it reads. On the device a copy: one 16-byte load
// (through a reference nvcc loads the four words one by one; PTX checked). On the host a
// reference: with the copy the 2D dam break's seq pressure pass ran 13 % slower than with the
// former scalar reads (measured; likely GCC copies the aligned record through the stack), with
// the reference as fast or faster.
// Either way the alias carries the const, so the kernels write no qualifier of their own (a
// `const` on a reference type draws nvcc's "type qualifiers are meaningless" warning).
#if UNISPH_DEVICE_CODE
template <class T, int D>
using VelocityPressureRead = const VelocityPressure<T, D>;
#else
template <class T, int D>
using VelocityPressureRead = const VelocityPressure<T, D>&;
#endif

// The write side, held by the kernels that refresh the records.
template <class T, int D>
struct NeighborRecordWriter {
  View<PositionVolume<T, D>> position_volume;
  View<VelocityPressure<T, D>> velocity_pressure;
  UNISPH_HOST_DEVICE void store(Index i, const Vec<T, D>& x, const Vec<T, D>& v, T p, T m, T rho) const {
    position_volume[i] = PositionVolume<T, D>{x, m / rho};
    velocity_pressure[i] = VelocityPressure<T, D>{v, p};
  }
  static NeighborRecordWriter make(KernelContext& c, FluidVariables<T, D>& fluid) {
    return {c.write(fluid.neighbor_position_volume), c.write(fluid.neighbor_velocity_pressure)};
  }
};

// f(j, record_j, pair, w) for every fluid neighbour j of i, with record_j = records[j] and
// w = weight(pair): the same j, order, pair geometry and w as
// search.for_each_weighted_neighbor(i, weight, ...). A direct search over particles in cell
// order (the device default), or over a list ordered by id walked by its runs (several ranks),
// takes x_j from the record instead of the target positions (the same bits while the records
// are current), so that a candidate costs one aligned load; other searches read the record of
// each neighbour they find. The rows of cells are
// NeighborSearch::for_each_candidate_range's, walked as NeighborSearch::for_each_direct_candidate
// walks them.
// Runs = false leaves the walk by runs out of the code (for a kernel's common case, where the
// caller knows search.targets.run_end is empty): the same neighbours in the same order.
template <bool Runs = true, class T, int D, class W, class F>
UNISPH_NEIGHBOR_LOOP UNISPH_HOST_DEVICE void for_each_neighbor_record(const NeighborSearch<T, D>& search,
                                                                      View<const PositionVolume<T, D>> records, Index i,
                                                                      const W& weight, F&& f) {
  const bool cell_order = search.targets.in_cell_order();
  if (search.uses_stored_lists() || (!cell_order && (!Runs || search.targets.run_end.empty()))) {
    search.for_each_weighted_neighbor(
        i, weight, [&](Index j, const NeighborPair<T, D>& pair, T w) { f(j, records[j], pair, w); });
    return;
  }
  const Vec<T, D> xi = search.sources[i];
  const auto candidates = [&](std::uint32_t first, std::uint32_t last) {
    for (std::uint32_t j = first; j < last; ++j) {
      if (search.inner && j == i) continue;
      const PositionVolume<T, D> record = records[j];
      NeighborPair<T, D> pair;
      if (search.targets.grid.test_pair(xi, record.position, pair.r_ij, pair.squared_distance)) {
        pair.complete_approximately();  // the device's rsqrt: 13 % of the 3D step (docs/sph.md)
        f(Index(j), record, static_cast<const NeighborPair<T, D>&>(pair), weight(pair));
      }
    }
  };
  search.for_each_candidate_range(xi, [&](std::uint32_t begin, std::uint32_t end) {
    if constexpr (!Runs) {
      candidates(begin, end);
    } else if (cell_order) {
      candidates(begin, end);
    } else {
      // A list ordered by id with ghosts (several ranks): its runs of consecutive indices, in
      // the list's order, the same arithmetic as in cell order (CellListView::run_end).
      for (std::uint32_t k = begin; k < end;) {
        const std::uint32_t stop = search.targets.run_end[k] < end ? search.targets.run_end[k] : end;
        const std::uint32_t first = search.targets.particles[k];
        candidates(first, first + (stop - k));
        k = stop;
      }
    }
  });
}

// Writes the records from the fluid variables (after a sort, a restore, or at the start).
template <class T, int D>
class RefreshNeighborRecords : public UpdateDynamics<RefreshNeighborRecords<T, D>> {
 public:
  explicit RefreshNeighborRecords(FluidVariables<T, D>& fluid) : fluid_(fluid) {}
  struct Kernel {
    View<const Vec<T, D>> position, velocity;
    View<const T> pressure, mass, density;
    NeighborRecordWriter<T, D> records;
    UNISPH_HOST_DEVICE void update(Index i, Real) const {
      records.store(i, position[i], velocity[i], pressure[i], mass[i], density[i]);
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");
  Kernel make_kernel(KernelContext& c) {
    return {c.read(fluid_.position), c.read(fluid_.velocity), c.read(fluid_.pressure),
            c.read(fluid_.mass),     c.read(fluid_.density),  NeighborRecordWriter<T, D>::make(c, fluid_)};
  }
  Index size() const { return fluid_.size(); }

 private:
  FluidVariables<T, D>& fluid_;
};

}  // namespace unisph::sph
