#pragma once
// NeighborRelation<T, D>: what an inner relation (a body with itself) and a contact relation
// (one body's particles with another's) share — the sources, the target cell list, the search
// method per policy, the stored lists and their staleness check, and the kernel-side
// NeighborSearch they hand out. InnerRelation and ContactRelation (inner_relation.hpp,
// contact_relation.hpp) only say which positions are the sources and whether j == i is skipped.

#include <cstdint>
#include <string>
#include <utility>

#include "unisph/dynamics/kernel_context.hpp"
#include "unisph/neighbor/search_method.hpp"
#include "unisph/neighbor/stored_neighbor_lists.hpp"

namespace unisph {

template <class T, int D>
class NeighborRelation {
 public:
  template <ExecutionPolicy P>
  SearchMethod method(P policy) const { return resolve_search_method(method_, policy); }
  void set_method(SearchMethod method) { method_ = method; }
  // Sources are particles [0, source_count) of the source positions; by default all of them.
  // A particle set with ghosts passes its owned count: ghosts are found but not updated.
  void set_source_count(Index count) { source_count_ = count; }
  Index source_count() const { return source_count_ == unset ? sources_.size() : source_count_; }

  // Call after the target cell list was built and before the kernels that use search(); builds
  // the stored lists when the method for the policy is SearchMethod::stored (a direct search
  // needs nothing but the cell list).
  template <ExecutionPolicy P>
  void update(P policy) {
    if (method(policy) == SearchMethod::stored) {
      lists_.build(policy, direct_search(policy), source_count());
      lists_built_from_ = targets_.builds();
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
    NeighborSearch<T, D> s{context.read(sources_), targets_.view(context), inner_, {}, {}, {}, 0, 0, {}};
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
    return {sources_.read(policy), targets_.view(policy), inner_, {}, {}, {}, 0, 0, {}};
  }

 protected:
  // `what` names the relation in error messages ("InnerRelation of 'Water'").
  NeighborRelation(DiscreteVariable<Vec<T, D>>& sources, CellLinkedList<T, D>& targets, bool inner,
                   SearchMethod method, std::string what, std::string lists_name)
      : sources_(sources),
        targets_(targets),
        inner_(inner),
        method_(method),
        what_(std::move(what)),
        lists_(std::move(lists_name)) {}

  DiscreteVariable<Vec<T, D>>& sources_;
  CellLinkedList<T, D>& targets_;

 private:
  static constexpr Index unset = ~Index(0);

  void check_lists(MemorySpace space) {
    if (lists_.source_count() != source_count() || lists_built_from_ != targets_.builds())
      throw Error(what_ +
                  ": stored neighbour lists are used but update(policy) was not called after the last build of "
                  "the cell list");
    if (lists_.built_in() != space)
      throw Error(what_ +
                  ": stored neighbour lists are laid out for the space they were built in; call update() with a "
                  "policy of the space whose kernels read them");
  }

  bool inner_;
  SearchMethod method_;
  std::string what_;
  StoredNeighborLists<T, D> lists_;
  Index source_count_ = unset;
  std::uint64_t lists_built_from_ = ~std::uint64_t(0);
};

}  // namespace unisph
