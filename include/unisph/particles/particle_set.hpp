#pragma once
// ParticleSet: the particles of one body — a registry of named per-particle variables, a
// stable id per particle, and the split between owned particles and ghosts.
//
// Owned particles are [0, owned_count()); ghosts, copies of particles owned by a neighbouring
// domain (another GPU or rank, once there are several), follow in
// [owned_count(), total_count()). Kernels update owned particles only and read both; every
// variable has total_count() elements. Reordering permutes owned particles only: ghosts are
// rewritten by each halo exchange.
//
// Ids: owned particle k of a new set gets id first_id + k ("ParticleId", sortable, output).
// Reordering moves the ids with the particles; index_of_id() maps id - first_id back to the
// current index of an owned particle, and is refreshed by every reorder().

#include <algorithm>
#include <cstdint>
#include <limits>
#include <span>
#include <string>

#include "unisph/exec/algorithms.hpp"
#include "unisph/particles/permute_bytes.hpp"
#include "unisph/particles/variable_registry.hpp"

namespace unisph {

inline constexpr VariableTag<std::uint64_t> particle_id_tag{"ParticleId"};

namespace particle_set_detail {
struct MapIdsToIndices {
  View<const std::uint64_t> ids;
  std::uint64_t first_id;
  View<std::uint32_t> index_of_id;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    index_of_id[ids[i] - first_id] = static_cast<std::uint32_t>(i);
  }
};
struct FillIndex {
  View<std::uint32_t> index;
  std::uint32_t value;
  UNISPH_HOST_DEVICE void operator()(Index i) const { index[i] = value; }
};
}  // namespace particle_set_detail

// index_of_id() of a particle that is no longer in the set (removed by shrink_owned).
inline constexpr std::uint32_t absent_particle_index = std::numeric_limits<std::uint32_t>::max();

// A set made in shares, each rank making only its own particles of one whole set: the whole
// set's size, and each owned particle's number in it (its id less first_id), ascending. A
// default one (whole = 0) stands for a set made whole: particle k is number k.
struct SetShare {
  std::uint64_t whole = 0;
  std::span<const std::uint64_t> numbers;
};

class ParticleSet {
 public:
  ParticleSet(std::string name, Index owned_count, Index ghost_count = 0, std::uint64_t first_id = 0,
              SetShare share = {})
      : name_(std::move(name)),
        owned_(owned_count),
        ghosts_(ghost_count),
        first_id_(first_id),
        variables_("particle set '" + name_ + "'", owned_count + ghost_count),
        id_count_(share.whole ? share.whole : owned_count),
        index_of_id_(name_ + ".IndexOfId", Index(id_count_)),
        scratch_(name_ + ".ReorderScratch") {
    if (owned_count >= Index(std::numeric_limits<std::uint32_t>::max()) ||
        share.whole >= std::uint64_t(std::numeric_limits<std::uint32_t>::max()))
      throw Error("particle set '" + name_ + "': " + std::to_string(std::max<std::uint64_t>(owned_count, share.whole)) +
                  " particles; particle indices are 32-bit");
    if (share.whole && share.numbers.size() != std::size_t(owned_count))
      throw Error("particle set '" + name_ + "': a share of " + std::to_string(owned_count) + " particles with " +
                  std::to_string(share.numbers.size()) + " numbers");
    DiscreteVariable<std::uint64_t>& ids = variables_.add(particle_id_tag, sortable_output_variable);
    View<std::uint64_t> id = ids.write(MemorySpace::host);
    View<std::uint32_t> index = index_of_id_.write(MemorySpace::host);
    if (share.whole)
      for (Index k = 0; k < index.size(); ++k) index[k] = absent_particle_index;
    for (Index k = 0; k < owned_count; ++k) {
      const std::uint64_t number = share.whole ? share.numbers[k] : k;
      if (number >= index_of_id_.size())
        throw Error("particle set '" + name_ + "': particle number " + std::to_string(number) + " of a set of " +
                    std::to_string(index_of_id_.size()));
      id[k] = first_id + number;
      index[number] = static_cast<std::uint32_t>(k);
    }
  }

  const std::string& name() const { return name_; }
  Index owned_count() const { return owned_; }
  Index ghost_count() const { return ghosts_; }
  Index total_count() const { return owned_ + ghosts_; }
  std::uint64_t first_id() const { return first_id_; }

  VariableRegistry& variables() { return variables_; }
  template <class T>
  DiscreteVariable<T>& add_variable(const std::string& name, VariableFlags flags = {}) {
    return variables_.add<T>(name, flags);
  }
  template <class T>
  DiscreteVariable<T>& add_variable(VariableTag<T> tag, VariableFlags flags = {}) {
    return variables_.add(tag, flags);
  }
  template <class T>
  DiscreteVariable<T>& variable(std::string_view name) {
    return variables_.get<T>(name);
  }
  template <class T>
  DiscreteVariable<T>& variable(VariableTag<T> tag) {
    return variables_.get(tag);
  }

  DiscreteVariable<std::uint64_t>& ids() { return variables_.get(particle_id_tag); }
  DiscreteVariable<std::uint32_t>& index_of_id() { return index_of_id_; }
  // The ids lie in [first_id, first_id + id_count()): the size of the set as made (whole).
  std::uint64_t id_count() const { return id_count_; }
  // Stops keeping index_of_id() (it becomes empty): a set split among ranks has ids over the
  // whole set, so the map would take 4 bytes per particle of the whole set on every rank, and
  // nothing there looks particles up by id.
  void drop_index_of_id() {
    map_ids_ = false;
    index_of_id_.resize(0);
  }

  // Makes room for `count` ghosts after the owned particles (their contents are the caller's
  // to fill: a halo exchange writes every ghost slot).
  void set_ghost_count(Index count) {
    ghosts_ = count;
    variables_.resize(total_count());
  }

  // Keeps the first `count` owned particles and drops the rest (the caller reorders the ones to
  // drop to the end first, e.g. particles that left the domain). Ids stay with their particles;
  // a dropped particle's id maps to absent_particle_index. For sets without ghosts.
  template <ExecutionPolicy P>
  void shrink_owned(P policy, Index count) {
    if (count > owned_)
      throw Error("particle set '" + name_ + "': cannot shrink " + std::to_string(owned_) + " owned particles to " +
                  std::to_string(count));
    if (ghosts_ != 0) throw Error("particle set '" + name_ + "': shrink_owned needs a set without ghosts");
    owned_ = count;
    variables_.resize(owned_);
    map_ids(policy, true);
  }

  // Takes `count` owned particles and no ghosts after the registry was resized to `count` from
  // outside (a migration between ranks, comm/migrate.hpp, which keeps the particles that stay
  // and appends the arrivals), and maps the ids again. Every id must lie in [first_id,
  // first_id + the owned count the set was made with): a set split among ranks is made whole on
  // each, so that its ids are global, and then keeps its share.
  template <ExecutionPolicy P>
  void adopt_owned(P policy, Index count) {
    if (variables_.size() != count)
      throw Error("particle set '" + name_ + "': adopt_owned(" + std::to_string(count) + ") but the variables hold " +
                  std::to_string(variables_.size()) + " particles");
    owned_ = count;
    ghosts_ = 0;
    map_ids(policy, true);
  }

  // Moves owned particle permutation[k] to index k, for every sortable variable, and
  // refreshes index_of_id(). `permutation` is a permutation of [0, owned_count()) in the
  // policy's memory space.
  template <ExecutionPolicy P>
  void reorder(P policy, View<const std::uint32_t> permutation) {
    if (permutation.size() != owned_)
      throw Error("particle set '" + name_ + "': a permutation of " + std::to_string(permutation.size()) +
                  " particles cannot reorder " + std::to_string(owned_) + " owned particles");
    variables_.for_each([&](VariableRegistry::Entry& e) {
      if (!e.flags.sortable || owned_ == 0) return;
      VariableBase& v = *e.variable;
      permute_in_place(policy, permutation, v.prepare(P::space, Access::read_write), v.element_size(), scratch_,
                       "particle reorder");
    });
    map_ids(policy, false);
  }

 private:
  // index_of_id() from the owned particles' ids (all entries cleared first where some ids may
  // have left), unless dropped.
  template <ExecutionPolicy P>
  void map_ids(P policy, bool clear) {
    if (!map_ids_) return;
    if (clear)
      particle_for(policy, index_of_id_.size(),
                   particle_set_detail::FillIndex{index_of_id_.write(policy), absent_particle_index});
    particle_for(policy, owned_,
                 particle_set_detail::MapIdsToIndices{ids().read(policy), first_id_,
                                                      clear ? index_of_id_.read_write(policy) : index_of_id_.write(policy)});
  }

  std::string name_;
  Index owned_;
  Index ghosts_;
  std::uint64_t first_id_;
  VariableRegistry variables_;
  std::uint64_t id_count_;
  bool map_ids_ = true;
  DiscreteVariable<std::uint32_t> index_of_id_;
  DiscreteVariable<std::uint32_t> scratch_;
};

}  // namespace unisph
