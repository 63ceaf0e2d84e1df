#pragma once
// ContactRelation<T, D>: the neighbours of one body's particles (the sources, e.g. fluid)
// among another body's particles (the targets, e.g. a wall), found through the target's cell
// linked list. Sources outside the target's box are clamped into its border cells for the
// search, so they still find the targets within the cutoff; a source with a NaN coordinate
// finds none.
//
//   ContactRelation<T, 3> fluid_wall(fluid.positions(), wall_cells);
//   wall_cells.build(policy); fluid_wall.update(policy);
//   fluid_wall.search(context).for_each_neighbor(i, ...)   // j indexes the wall's particles
//
// The rest of the interface is NeighborRelation's (neighbor_relation.hpp).

#include "unisph/neighbor/neighbor_relation.hpp"

namespace unisph {

template <class T, int D>
class ContactRelation : public NeighborRelation<T, D> {
 public:
  ContactRelation(DiscreteVariable<Vec<T, D>>& sources, CellLinkedList<T, D>& targets,
                  SearchMethod method = SearchMethod::automatic)
      : NeighborRelation<T, D>(sources, targets, false, method,
                               "ContactRelation of '" + sources.name() + "' with '" + targets.positions().name() + "'",
                               sources.name() + ".ContactWith." + targets.positions().name()) {}

  CellLinkedList<T, D>& target_cell_list() { return this->targets_; }
};

}  // namespace unisph
