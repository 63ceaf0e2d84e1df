#pragma once
// What a view takes from one level of a container: the first position it uses (offset), how
// many positions the level has for it (element count) and the distance between two visited
// positions (jump). The seed calls this the RuntimeTuple, with getOffset(), getNbElements()
// and getJumpsize(); each value can be known at run time (RuntimeTuple) or at compile time
// (CompileTimeTuple, which the compiler folds away).
//
// Argument order: (offset, element count, jump), as in the seed's list of requirements and in
// four of its five uses; one slide ("Jedes zweite Frame") writes (offset, jumpsize, nbElements),
// which would give a jump of -1 there. The aggregate also takes designated initializers,
// RuntimeTuple{.offset = 0, .count = all, .jump = 2}, which leave no doubt.
//
// Whether a view uses this element count at all is decided by the container's traits
// (container_traits.hpp): a frame has a number of slots fixed at compile time and ignores it.

#include <type_traits>

#include "unisph/core/config.hpp"

namespace unisph::iter {

// An element count meaning "every element the container holds" (the seed writes -1).
inline constexpr Index all = ~Index(0);

struct RuntimeTuple {
  Index offset = 0;
  Index count = all;
  Index jump = 1;

  UNISPH_HOST_DEVICE constexpr Index get_offset() const { return offset; }
  UNISPH_HOST_DEVICE constexpr Index get_element_count() const { return count; }
  UNISPH_HOST_DEVICE constexpr Index get_jump() const { return jump; }
};

template <Index Offset = 0, Index Count = all, Index Jump = 1>
struct CompileTimeTuple {
  static_assert(Jump >= 1, "a view's jump size is the distance between two visited elements and must be at least 1.");
  UNISPH_HOST_DEVICE static constexpr Index get_offset() { return Offset; }
  UNISPH_HOST_DEVICE static constexpr Index get_element_count() { return Count; }
  UNISPH_HOST_DEVICE static constexpr Index get_jump() { return Jump; }
};

template <class R>
concept RuntimeVariables = std::is_trivially_copyable_v<R> && requires(const R& r) {
  { r.get_offset() } -> std::convertible_to<Index>;
  { r.get_element_count() } -> std::convertible_to<Index>;
  { r.get_jump() } -> std::convertible_to<Index>;
};

static_assert(RuntimeVariables<RuntimeTuple>);
static_assert(RuntimeVariables<CompileTimeTuple<>>);

}  // namespace unisph::iter
