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
// for direct search it does nothing (the cell list is all a direct search needs).

#include <cstdint>
#include <string>

#include "unisph/dynamics/kernel_context.hpp"
#include "unisph/neighbor/search_method.hpp"
#include "unisph/neighbor/stored_neighbor_lists.hpp"

namespace unisph {

template <class T, int D>
class InnerRelation {
 public:
  explicit InnerRelation(CellLinkedList<T, D>& cells, SearchMethod method = SearchMethod::automatic)
      : cells_(cells), method_(method), lists_(cells.positions().name() + ".Inner") {}

  CellLinkedList<T, D>& cell_list() { return cells_; }
  template <ExecutionPolicy P>
  SearchMethod method(P policy) const { return resolve_search_method(method_, policy); }
  void set_method(SearchMethod method) { method_ = method; }
  // Sources are particles [0, source_count); by default every particle in the cell list.
  // A particle set with ghosts passes its owned count: ghosts are found but not updated.
  void set_source_count(Index count) { source_count_ = count; }
  Index source_count() const { return source_count_ == unset ? cells_.positions().size() : source_count_; }

  // Call after cells.build(policy) and before the kernels that use search().
  template <ExecutionPolicy P>
  void update(P policy) {
    if (method(policy) == SearchMethod::stored) {
      lists_.build(policy, direct_search(policy), source_count());
      lists_built_from_ = cells_.builds();
    }
  }

  // As update(policy), and with stored lists also their weight column: weight(pair) for each
  // pair, for kernels that ask for it with search(context, weight) and read it through
  // NeighborSearch::for_each_weighted_neighbor (a direct search computes it pair by pair).
  template <ExecutionPolicy P, class W>
  void update(P policy, const W& weight) {
    update(policy);
    if (method(policy) == SearchMethod::stored) lists_.fill_weights(policy, weight);
  }

  template <ExecutionPolicy P>
  NeighborSearch<T, D> search(P policy) {
    NeighborSearch<T, D> s = direct_search(policy);
    if (method(policy) == SearchMethod::stored) {
      check_lists(P::space);
      s.list_counts = lists_.counts().read(P::space);
      s.list_neighbors = lists_.neighbors().read(P::space);
      s.list_pairs = lists_.pairs().read(P::space);
      s.list_source_stride = lists_.source_stride(P::space);
      s.list_slot_stride = lists_.slot_stride(P::space);
    }
    return s;
  }
  NeighborSearch<T, D> search(KernelContext& context) {
    NeighborSearch<T, D> s{context.read(cells_.positions()), cells_.view(context), true, {}, {}, {}, 0, 0, {}};
    const bool stored = context.space() == MemorySpace::device
                            ? method(ParallelDevicePolicy{}) == SearchMethod::stored
                            : method(ParallelPolicy{}) == SearchMethod::stored;
    if (stored) {
      check_lists(context.space());
      s.list_counts = context.read(lists_.counts());
      s.list_neighbors = context.read(lists_.neighbors());
      s.list_pairs = context.read(lists_.pairs());
      s.list_source_stride = lists_.source_stride(context.space());
      s.list_slot_stride = lists_.slot_stride(context.space());
    }
    return s;
  }

  // search(policy) / search(context), with the lists' weight column when it holds `weight`
  // for the current lists (else a weighted loop computes the weights).
  template <ExecutionPolicy P, class W>
  NeighborSearch<T, D> search(P policy, const W& weight) {
    NeighborSearch<T, D> s = search(policy);
    if (s.uses_stored_lists() && lists_.has_weights_of(weight)) s.list_weights = lists_.weights().read(P::space);
    return s;
  }
  template <class W>
  NeighborSearch<T, D> search(KernelContext& context, const W& weight) {
    NeighborSearch<T, D> s = search(context);
    if (s.uses_stored_lists() && lists_.has_weights_of(weight)) s.list_weights = context.read(lists_.weights());
    return s;
  }

  StoredNeighborLists<T, D>& stored_lists() { return lists_; }

  // A direct search whatever the method (what the stored lists are built from).
  template <ExecutionPolicy P>
  NeighborSearch<T, D> direct_search(P policy) {
    return {cells_.positions().read(policy), cells_.view(policy), true, {}, {}, {}, 0, 0, {}};
  }

 private:
  static constexpr Index unset = ~Index(0);

  void check_lists(MemorySpace space) {
    if (lists_.source_count() != source_count() || lists_built_from_ != cells_.builds())
      throw Error("InnerRelation of '" + cells_.positions().name() +
                  "': stored neighbour lists are used but update(policy) was not called after the last build of "
                  "the cell list");
    if (lists_.built_in() != space)
      throw Error(std::string("InnerRelation of '" + cells_.positions().name() + "'") +
                  ": stored neighbour lists are laid out for the space they were built in; call update() with a "
                  "policy of the space whose kernels read them");
  }

  CellLinkedList<T, D>& cells_;
  SearchMethod method_;
  StoredNeighborLists<T, D> lists_;
  Index source_count_ = unset;
  std::uint64_t lists_built_from_ = ~std::uint64_t(0);
};

}  // namespace unisph
