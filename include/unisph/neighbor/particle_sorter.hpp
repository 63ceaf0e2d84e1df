#pragma once
// ParticleSorter<T, D>: reorders a particle set by the Morton key of each particle's cell, so
// that particles close in space are close in memory (neighbour loops then read contiguous
// memory instead of scattered lines). Keys -> sort_pairs (radix sort, CUB on the device) of
// (key, index) -> every sortable variable permuted, ids kept (ParticleSet::reorder).
// Only the key bits the grid can set are sorted (fewer radix passes for small grids).
// Particles with a NaN coordinate go last; out-of-box ones sort with their border cell.
// After a sort, every cell list over the set is stale: rebuild it before searching.
//
// SortOrder::cell_index sorts by the row-major cell index instead (the cell list's own
// order): the particles of each cell, and of each row of three cells, are then contiguous,
// and the cell list's direct search reads them without indirection (see
// cell_linked_list.hpp). Morton order keeps more of the 3D neighbourhood together in
// memory; docs/neighbor_search.md compares the two.
//
// SortOrder::cell_index_then_id sorts by (cell index, id): cell order with the ids ascending
// within each cell, which is the order of a cell list ordered by id
// (CellLinkedList::order_within_cells_by_id). Such a list over the sorted set is then in cell
// order (no indirection), and its neighbours are visited in the same order as through the
// indirection of any other arrangement of the same particles (ghosts from other ranks
// included): the order that makes a run on several ranks the same bits as on one.

#include <cstdint>

#include "unisph/exec/algorithms.hpp"
#include "unisph/exec/workspace.hpp"
#include "unisph/neighbor/cell_linked_list.hpp"
#include "unisph/core/morton_key.hpp"
#include "unisph/neighbor/search_grid.hpp"
#include "unisph/particles/particle_set.hpp"

namespace unisph {

enum class SortOrder { morton, cell_index, cell_index_then_id };

namespace sorter_detail {
template <class T, int D>
struct ComputeKeys {
  SearchGrid<T, D> grid;
  bool morton;
  bool flag_outside;       // out-of-box particles go last too (as in a flagging cell list)
  std::uint64_t last_key;  // for particles with a NaN coordinate
  View<const Vec<T, D>> positions;
  View<std::uint64_t> keys;
  View<std::uint32_t> indices;
  // SortOrder::cell_index_then_id: the key is shifted up by id_bits and (id - first_id) fills
  // them (an id outside the set's id_count ids as id_count); ids empty otherwise.
  View<const std::uint64_t> ids;
  std::uint64_t first_id = 0;
  std::uint64_t id_count = 0;
  int id_bits = 0;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    const CellPlacement<D> p = grid.place(positions[i]);
    const bool last = (p.status & placement_non_finite) || (flag_outside && p.status != placement_inside);
    std::uint64_t key = last ? last_key : (morton ? morton_key<D>(p.cell) : std::uint64_t(grid.linear_index(p.cell)));
    if (!ids.empty()) {
      const std::uint64_t id = ids[i] - first_id;
      key = (key << id_bits) | (id < id_count ? id : id_count);
    }
    keys[i] = key;
    indices[i] = static_cast<std::uint32_t>(i);
  }
};
}  // namespace sorter_detail

template <class T, int D>
class ParticleSorter {
 public:
  // `every` > 0: sort_if_due() sorts at steps 0, every, 2 * every, ... `outside`: as the
  // cell lists over the set (flagged particles then sort last, keeping the cell order).
  ParticleSorter(ParticleSet& particles, DiscreteVariable<Vec<T, D>>& positions, const SearchGrid<T, D>& grid,
                 Index every = 1, SortOrder order = SortOrder::morton,
                 OutsideParticles outside = OutsideParticles::clamp)
      : particles_(particles),
        positions_(positions),
        grid_(grid),
        every_(every == 0 ? 1 : every),
        order_(order),
        flag_outside_(outside == OutsideParticles::flag),
        keys_(particles.name() + ".MortonKey"),
        permutation_(particles.name() + ".SortPermutation") {
    int largest = 1;
    for (int a = 0; a < D; ++a) largest = grid.cells[a] > largest ? grid.cells[a] : largest;
    // + 1: room for the key of the particles sorted last, above every cell's.
    if (order == SortOrder::morton) {
      key_bits_ = morton_key_bits(D, largest) + 1;
    } else {
      key_bits_ = 0;
      while ((std::uint64_t(1) << key_bits_) < grid.cell_count()) ++key_bits_;
      key_bits_ += 1;
    }
    if (order == SortOrder::cell_index_then_id) {
      id_count_ = particles.id_count();  // ids lie in [first_id, first_id + id_count)
      while (id_bits_ < 64 && (std::uint64_t(1) << id_bits_) <= id_count_) ++id_bits_;
      if (key_bits_ + id_bits_ > 64)
        throw Error("ParticleSorter of '" + particles.name() + "': " + std::to_string(grid.cell_count()) + " cells and " +
                    std::to_string(id_count_) + " ids need " + std::to_string(key_bits_ + id_bits_) +
                    " key bits; the sort keys have 64");
    }
  }

  // The keys and the permutation live only within the sort (a WorkspaceScope: on the device
  // they share memory with the other phases of a step's end; 12 bytes per particle).
  template <ExecutionPolicy P>
  void sort(P policy) {
    const Index n = particles_.owned_count();
    WorkspaceScope scope(policy);
    const View<std::uint64_t> keys = scope.take(policy, keys_, n);
    const View<std::uint32_t> permutation = scope.take(policy, permutation_, n);
    const bool by_id = order_ == SortOrder::cell_index_then_id;
    particle_for(policy, n,
                 sorter_detail::ComputeKeys<T, D>{grid_, order_ == SortOrder::morton, flag_outside_,
                                                  std::uint64_t(1) << (key_bits_ - 1),
                                                  positions_.read(policy), keys, permutation,
                                                  by_id ? View<const std::uint64_t>(particles_.ids().read(policy))
                                                        : View<const std::uint64_t>{},
                                                  particles_.first_id(), id_count_, id_bits_});
    sort_pairs(policy, keys, permutation, 0, key_bits_ + id_bits_);
    particles_.reorder(policy, View<const std::uint32_t>(permutation));
    ++sorts_;
  }

  // Sorts when `step` is a multiple of the interval; true when it did.
  template <ExecutionPolicy P>
  bool sort_if_due(P policy, Index step) {
    if (step % every_ != 0) return false;
    sort(policy);
    return true;
  }

  // The bits sorted: those of the cell key (plus one for the particles sorted last) below
  // id_bits() bits of the id (SortOrder::cell_index_then_id; 0 otherwise).
  int key_bits() const { return key_bits_ + id_bits_; }
  int id_bits() const { return id_bits_; }
  Index sorts() const { return sorts_; }

 private:
  ParticleSet& particles_;
  DiscreteVariable<Vec<T, D>>& positions_;
  SearchGrid<T, D> grid_;
  Index every_;
  SortOrder order_;
  bool flag_outside_;
  int key_bits_ = 1;
  int id_bits_ = 0;
  std::uint64_t id_count_ = 0;
  DiscreteVariable<std::uint64_t> keys_;  // the host's storage of the sort's keys (WorkspaceScope)
  DiscreteVariable<std::uint32_t> permutation_;
  Index sorts_ = 0;
};

}  // namespace unisph
