#pragma once
// InnerRelation<T, D>: the neighbours of a body's particles among its own particles (j != i),
// found through the body's cell linked list.
//
//   CellLinkedList<T, 3> cells(body.positions(), box, cutoff);
//   InnerRelation<T, 3> inner(cells);
//   cells.build(policy); inner.update(policy);        // after the particles moved
//   NeighborSearch<T, 3> s = inner.search(context);   // in a method's make_kernel
//
// update() builds the stored lists when the method for the policy is SearchMethod::stored;
// for direct search it does nothing (the cell list is all a direct search needs). The rest of
// the interface is NeighborRelation's (neighbor_relation.hpp).

#include "unisph/neighbor/neighbor_relation.hpp"

namespace unisph {

template <class T, int D>
class InnerRelation : public NeighborRelation<T, D> {
 public:
  explicit InnerRelation(CellLinkedList<T, D>& cells, SearchMethod method = SearchMethod::automatic)
      : NeighborRelation<T, D>(cells.positions(), cells, true, method,
                               "InnerRelation of '" + cells.positions().name() + "'",
                               cells.positions().name() + ".Inner") {}

  CellLinkedList<T, D>& cell_list() { return this->targets_; }
};

}  // namespace unisph
