#pragma once
// PeriodicCellList<T, D>: periodic boundaries for the neighbour search by wrapped cell indices
// (issue 21; the other way is ghost images, periodic_images.hpp). It owns a CellLinkedList over
// the particles' positions on a grid whose cells divide the box exactly along the periodic axes
// (SearchGrid::make_periodic), and hands out the kernel-side walk (PeriodicCellWalk,
// periodic_cell_walk.hpp) that finds minimum-image neighbours through it. No particle is copied:
// per step a solver calls
//
//   PeriodicCellList<T, 3> cells(body.positions(), domain, {true, false, true}, cutoff);
//   cells.wrap(policy);    // particles that left the box across a periodic axis come back in
//   cells.build(policy);   // the cell list (CellLinkedList::build on the divided grid)
//   PeriodicCellWalk<T, 3> walk = cells.inner_walk(context);   // in a method's make_kernel
//
// wrap() is PeriodicImages::wrap's kernel (the same bits). The box must be at least two cutoffs
// wide along every periodic axis (as for images; refused with one unisph::Error line otherwise).
// Grids with fewer than 2 reach + 1 cells along a periodic axis are allowed: the walk then meets
// some cells twice, with different shifts, and finds each pair once (periodic_cell_walk.hpp).

#include <array>
#include <limits>
#include <string>

#include "unisph/core/box.hpp"
#include "unisph/core/error.hpp"
#include "unisph/dynamics/kernel_context.hpp"
#include "unisph/neighbor/cell_linked_list.hpp"
#include "unisph/neighbor/periodic_cell_walk.hpp"
#include "unisph/neighbor/periodic_images.hpp"

namespace unisph {

template <class T, int D>
class PeriodicCellList {
 public:
  using Position = Vec<T, D>;

  // A cell list over `positions` (all of them) in `box`, periodic along the axes a with
  // periodic[a], for neighbours closer than `cutoff`, with cells of at least `cell_size` (0: the
  // cutoff; down to cutoff / 4) — exactly L_a / floor(L_a / cell_size) along periodic axes.
  // Throws unisph::Error (one line) for a box narrower than two cutoffs along a periodic axis,
  // and what SearchGrid::make throws.
  PeriodicCellList(DiscreteVariable<Position>& positions, const Box<T, D>& box, const std::array<bool, D>& periodic,
                   T cutoff, OutsideParticles outside = OutsideParticles::clamp, T cell_size = T(0))
      : cells_(positions, checked_grid(positions, box, periodic, cutoff, cell_size), outside) {
    domain_.lower = box.lower;
    domain_.upper = box.upper;
    domain_.periodic = 0u;
    for (int a = 0; a < D; ++a) {
      domain_.length[a] = box.upper[a] - box.lower[a];
      if (periodic[a]) domain_.periodic |= 1u << a;
    }
    domain_.width = T(0);  // no images
  }

  const SearchGrid<T, D>& grid() const { return cells_.grid(); }
  Box<T, D> box() const { return {domain_.lower, domain_.upper}; }
  bool periodic(int axis) const { return domain_.is_periodic(axis); }
  CellLinkedList<T, D>& cells() { return cells_; }
  DiscreteVariable<Position>& positions() { return cells_.positions(); }

  // Moves the particles [0, count) (default: all) that left the box across a periodic axis back
  // in: x -= L floor((x - lower) / L); particles inside are left bit for bit. Asynchronous.
  template <ExecutionPolicy P>
  void wrap(P policy, Index count = ~Index(0)) {
    if (count > positions().size()) count = positions().size();
    if (domain_.periodic == 0u || count == 0) return;
    particle_for(policy, count, periodic_detail::WrapIntoBox<T, D>{domain_, positions().read_write(policy)});
  }

  // Rebuilds the cell list from the current positions (which wrap() should have brought into the
  // box along the periodic axes). Asynchronous on the device.
  template <ExecutionPolicy P>
  void build(P policy) {
    cells_.build(policy);
  }

  // The walk of the list's own particles (j != i).
  template <ExecutionPolicy P>
  PeriodicCellWalk<T, D> inner_walk(P policy) {
    return {positions().read(policy), cells_.view(policy), true};
  }
  PeriodicCellWalk<T, D> inner_walk(KernelContext& context) {
    return {context.read(positions()), cells_.view(context), true};
  }
  // The walk of other positions (e.g. another body's, inside the box) among the list's particles.
  template <ExecutionPolicy P>
  PeriodicCellWalk<T, D> contact_walk(P policy, DiscreteVariable<Position>& sources) {
    return {sources.read(policy), cells_.view(policy), false};
  }
  PeriodicCellWalk<T, D> contact_walk(KernelContext& context, DiscreteVariable<Position>& sources) {
    return {context.read(sources), cells_.view(context), false};
  }

 private:
  static SearchGrid<T, D> checked_grid(const DiscreteVariable<Position>& positions, const Box<T, D>& box,
                                       const std::array<bool, D>& periodic, T cutoff, T cell_size) {
    for (int a = 0; a < D; ++a) {
      const T length = box.upper[a] - box.lower[a];
      if (periodic[a] && !(length >= T(2) * cutoff))
        throw Error("PeriodicCellList of '" + positions.name() + "': the box " + to_string(box) + " is " +
                    std::to_string(length) + " wide along periodic axis " + std::to_string(a) +
                    ", narrower than two cutoffs (2 x " + std::to_string(cutoff) +
                    "): a particle could have two images within the cutoff");
    }
    return SearchGrid<T, D>::make_periodic(box, cutoff, periodic, cell_size);
  }

  CellLinkedList<T, D> cells_;
  periodic_detail::PeriodicDomain<T, D> domain_{};
};

}  // namespace unisph
