#pragma once
// iter::View<Container, Direction, Collectivity, Runtime, Child>: begin() and end() over one
// level of a hierarchical container, and through Child over the levels below it (seed 002,
// "Parallel Particle Iterators"). One algorithm written against views runs over every container
// that has ContainerTraits (frames, supercells, containers of supercells, ...), in host code,
// in device code, forward or backward, and shared by several threads.
//
// Not to be confused with unisph::View<T> (memory/view.hpp), the flat pointer + size that
// variables hand out. An iter::View holds such pointers too (inside its container's handle),
// and walks the structure they describe.
//
//   using ParticlesOfFrame = View<Frame<P, 5>, direction::Forward, collectivity::None, RuntimeTuple>;
//   View<Supercell<Frame<P, 5>>, direction::Forward, collectivity::None, RuntimeTuple, ParticlesOfFrame>
//       particles(supercell, RuntimeTuple{0, all, 1}, ParticlesOfFrame(nullptr, RuntimeTuple{0, all, 1}));
//   for (auto it = particles.begin(); it != particles.end(); ++it)
//     if (auto slot = *it) use(*slot);        // the free slots of the last frame are invalid
//
// Which positions a level visits. C is the element count (the container's own for a frame,
// whose number of slots is a compile-time trait; the runtime count clipped to the container's
// size otherwise), o the offset, j the jump, counted in walking order (Backward starts at
// the last element). With a collectivity of size S, worker r uses o' = o + r j and j' = S j.
// The worker makes trips = ceil(C / j') - floor(o' / j') trips and visits o', o' + j', ...;
// positions at or past C are padding and dereference to an invalid SlotRef. For every
// offset below the jump the number of trips is the same, ceil(C / j'), so workers that differ
// only in their offset (r, or o = thread id with j = thread count as in the seed) stay in
// step and may meet at a barrier inside the loop.
//
// With a Child, the view yields the child's slots: for each trip of this level it walks the
// child view (a prototype built with nullptr instead of a container) over that element. A
// padding position gives the child an empty container: a frame of N empty slots (so that
// nested collective walks keep their trip counts equal), a supercell with no frames. Trips of
// this level whose child walk is empty are skipped.
//
// for_each(f) visits the same slots as the iterators, as one plain loop per level: the fast
// form (the iterator loop measures 1.1 to 1.9 times the hand-written loop, for_each within a
// few per cent; docs/views.md). children() is the range of the child views, for a range-for per
// level (`for (auto frame : view.children()) for (auto slot : frame)`), which compilers treat
// as nested loops (measured on the CPU: as fast as the hand loop over all particles).

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <ranges>
#include <type_traits>
#include <utility>

#include "unisph/core/config.hpp"
#include "unisph/iter/collectivity.hpp"
#include "unisph/iter/container_traits.hpp"
#include "unisph/iter/direction.hpp"
#include "unisph/iter/runtime.hpp"
#include "unisph/iter/slot_ref.hpp"

namespace unisph::iter {

// The Child of a view with no level below it.
struct NoChild {};

template <class Container, class Direction = direction::Forward, class Collectivity = collectivity::None,
          class Runtime = RuntimeTuple, class Child = NoChild>
class View;

namespace detail {

template <class V>
struct is_iter_view : std::false_type {};
template <class C, class D, class K, class R, class Ch>
struct is_iter_view<View<C, D, K, R, Ch>> : std::true_type {};

template <class Child>
struct child_types {
  using iterator = NoChild;
};
template <class C, class D, class K, class R, class Ch>
struct child_types<View<C, D, K, R, Ch>> {
  using iterator = typename View<C, D, K, R, Ch>::iterator;
};

template <class Container, class Child>
constexpr bool check_child() {
  if constexpr (!std::is_same_v<Child, NoChild>) {
    static_assert(is_iter_view<Child>::value,
                  "iter::View: the Child parameter must be another iter::View (the view one level down, e.g. the "
                  "particles of a frame under the frames of a supercell) or iter::NoChild.");
    if constexpr (is_iter_view<Child>::value) {
      static_assert(ContainerWithChildren<Container>,
                    "iter::View: this container has no level below it (its ContainerTraits have no child()), so its "
                    "view cannot have a Child view; use iter::NoChild.");
      if constexpr (ContainerWithChildren<Container>) {
        static_assert(std::is_same_v<typename ContainerTraits<Container>::ChildContainer, typename Child::container_type>,
                      "iter::View: the Child view must walk the containers one level down (ContainerTraits<Container>"
                      "::ChildContainer, e.g. the supercell's frame type, const where the supercell's frames are const).");
      }
    }
  }
  return true;
}

// Where the walk of one level stands: the positions this worker visits and the cursor at the
// current one.
template <class Container, bool Forward>
struct LevelWalk {
  using Traits = ContainerTraits<Container>;
  // Where elements sit in one array, the cursor follows from the position; a list keeps it.
  static constexpr bool random_access = requires { requires Traits::random_access; };

  // Walking forward over a container whose elements fill its first slots (a frame), one
  // comparison tells whether a position holds an element.
  static constexpr bool filled_front =
      random_access && Forward && requires(const typename Traits::Handle& h) { Traits::filled_prefix(h); };

  // Containers whose element counts always fit 32 bits (ContainerTraits::small_positions: the
  // places of a row of cells, ...) are walked with 32-bit positions: on the GPU a 64-bit counter
  // takes two registers and two instructions per step and per comparison.
  static constexpr bool small = requires { requires Traits::small_positions; };
  using Position = std::conditional_t<small, std::uint32_t, Index>;

  typename Traits::Handle handle{};
  typename Traits::Cursor stored_cursor{};  // lists only
  Position position = 0;                    // in walking order
  Position end_position = 0;                // the position after the last trip
  Position jump = 1;
  Position count = 0;       // positions below count may hold elements, the others are padding
  Position filled_end = 0;  // filled_front only: positions below it hold elements

  // Positions only grow, by the jump, up to end_position = offset + trips * jump. `>=` rather than
  // `==` lets compilers count the trips of a loop over padding positions and drop it where the
  // body does nothing with an invalid slot (nvcc kept such empty loops, one per frame, with `==`).
  UNISPH_HOST_DEVICE constexpr bool at_end() const { return position >= end_position; }
  UNISPH_HOST_DEVICE constexpr typename Traits::Cursor cursor() const {
    if constexpr (random_access)
      return Traits::start(handle, position, Forward);
    else
      return stored_cursor;
  }
  UNISPH_HOST_DEVICE constexpr bool holds_element() const {
    if constexpr (filled_front)
      return position < filled_end;
    else
      return position < count && Traits::holds_element(handle, cursor());
  }
  // Along a list a jump of k costs k dependent loads after the work on this trip's element.
  // Where the walk skips elements, the container may fetch the first link ahead while the work
  // goes on (views_bench's strided walk on the 2-core VM: 1.41 -> 0.98 of the hand loop with
  // for_each); with jump 1 the link follows the element's own data, and fetching it ahead made
  // the walk over all particles slower there (1.14).
  // (A requires-expression naming the members through `this` is false under GCC 12, so the
  // test names its own parameters.)
  static constexpr bool fetches_ahead =
      requires(const typename Traits::Handle& h, const typename Traits::Cursor& c) { Traits::prefetch_step(h, c); };
  UNISPH_ALWAYS_INLINE UNISPH_HOST_DEVICE constexpr void prefetch_step() const {
    if constexpr (fetches_ahead)
      if (jump > 1 && holds_element()) Traits::prefetch_step(handle, stored_cursor);
  }
  UNISPH_HOST_DEVICE constexpr void advance() {
    position += jump;
    if constexpr (!random_access)
      if (position < count) stored_cursor = Traits::step(handle, stored_cursor, jump, Forward);
  }
};

}  // namespace detail

template <class Container, class Direction, class Collectivity, class Runtime, class Child>
class View : public std::ranges::view_base {
  static_assert(HasContainerTraits<Container>,
                "iter::View<Container, ...>: there is no ContainerTraits<Container>, so the view does not know how to "
                "walk this container; specialise unisph::iter::ContainerTraits for it (see iter/container_traits.hpp).");
  static_assert(!HasContainerTraits<Container> || ViewableContainer<Container>,
                "iter::View<Container, ...>: ContainerTraits<Container> must define Handle, Component, Cursor, "
                "needs_runtime_size and empty_handle() (see iter/container_traits.hpp).");
  static_assert(direction::is_direction_v<Direction>,
                "iter::View: Direction must be iter::direction::Forward or iter::direction::Backward.");
  static_assert(collectivity::Collectivity<Collectivity>,
                "iter::View: Collectivity must say who shares the walk (rank(), size(), sync(), is_mover()) and be "
                "trivially copyable: iter::collectivity::None, HostTeam or DeviceBlock.");
  static_assert(RuntimeVariables<Runtime>,
                "iter::View: Runtime must give get_offset(), get_element_count() and get_jump() and be trivially "
                "copyable: iter::RuntimeTuple (run-time values) or iter::CompileTimeTuple<offset, count, jump>.");
  static_assert(detail::check_child<Container, Child>());

 public:
  // Public so that the nested iterator sees them under every compiler (nvcc 13 refused private ones).
  using Traits = ContainerTraits<Container>;
  static constexpr bool has_child = !std::is_same_v<Child, NoChild>;
  static constexpr bool forward = Direction::is_forward;
  using Walk = detail::LevelWalk<Container, forward>;
  using ChildIterator = typename detail::child_types<Child>::iterator;
  // The container says which slots hold elements as one block at its front (frames do).
  static constexpr bool filled_in_one_block = Walk::random_access && requires(const typename Traits::Handle& h) {
    { Traits::filled_prefix(h) } -> std::convertible_to<Index>;
    { Traits::slot_count(h) } -> std::convertible_to<Index>;
  };

  // Every trip of this level is an element: one worker (no collectivity) walks from the first
  // element with jump 1 (compile-time offset 0 and jump 1), so no position is padding, and the
  // container says every slot holds one (ContainerTraits::every_slot_filled). The walk then
  // hands out its elements without the test of each trip: the test and the empty alternative
  // kept registers live in the GPU neighbour kernels (a stencil walk: 105 registers instead of
  // 80 in the 3D double pressure relaxation, ptxas -v).
  static constexpr bool dense = std::is_same_v<Collectivity, collectivity::None> &&
                                requires { requires Runtime::get_offset() == 0 && Runtime::get_jump() == 1; } &&
                                requires { requires Traits::every_slot_filled; };

  template <class V>
  struct slot_of {
    using type = typename V::slot_type;
  };
  // A container whose slots name their elements by value (ContainerTraits::slot(h, cursor): a
  // package's index, a data point's address) hands out its own slot type; the others a pointer.
  static constexpr bool value_slots = requires(const typename Traits::Handle& h, const typename Traits::Cursor& c) {
    Traits::slot(h, c);
  };
  template <class Unused>
  struct slot_of_leaf {
    using type = SlotRef<typename ContainerTraits<Container>::Component>;
  };
  template <class Unused>
  struct value_slot_of_leaf {
    using type = decltype(ContainerTraits<Container>::slot(std::declval<const typename ContainerTraits<Container>::Handle&>(),
                                                           std::declval<const typename ContainerTraits<Container>::Cursor&>()));
  };

  using container_type = Container;
  using handle_type = typename Traits::Handle;
  using direction_type = Direction;
  using collectivity_type = Collectivity;
  using runtime_type = Runtime;
  using child_type = Child;
  // What dereferencing an iterator gives: a slot of the lowest level.
  using slot_type =
      typename std::conditional_t<has_child, slot_of<Child>,
                                  std::conditional_t<value_slots, value_slot_of_leaf<Container>, slot_of_leaf<Container>>>::type;

  // The slot of a position that holds an element.
  UNISPH_HOST_DEVICE static constexpr slot_type filled_slot(const handle_type& h, const typename Traits::Cursor& c) {
    if constexpr (value_slots)
      return Traits::slot(h, c);
    else
      return slot_type::of(Traits::element(h, c));
  }

  class iterator {
   public:
    using value_type = slot_type;
    using reference = slot_type;
    using difference_type = std::ptrdiff_t;
    using iterator_concept = std::forward_iterator_tag;
    using iterator_category = std::input_iterator_tag;  // dereferencing yields a value, not a reference

    iterator() = default;

    UNISPH_HOST_DEVICE constexpr slot_type operator*() const {
      if constexpr (has_child)
        return *child_;
      else
        return walk_.holds_element() ? filled_slot(walk_.handle, walk_.cursor()) : slot_type();
    }
    UNISPH_HOST_DEVICE constexpr iterator& operator++() {
      if constexpr (has_child) {
        ++child_;
        if (child_.at_end()) {
          walk_.advance();
          descend();
        }
      } else {
        walk_.advance();
      }
      return *this;
    }
    UNISPH_HOST_DEVICE constexpr iterator operator++(int) {
      iterator before = *this;
      ++*this;
      return before;
    }
    UNISPH_HOST_DEVICE constexpr bool at_end() const { return walk_.at_end(); }

    // Iterators of the same view compare by where they stand.
    friend UNISPH_HOST_DEVICE constexpr bool operator==(const iterator& a, const iterator& b) {
      if (a.at_end() || b.at_end()) return a.at_end() == b.at_end();
      if constexpr (has_child)
        return a.walk_.position == b.walk_.position && a.child_ == b.child_;
      else
        return a.walk_.position == b.walk_.position;
    }
    friend UNISPH_HOST_DEVICE constexpr bool operator==(const iterator& a, std::default_sentinel_t) {
      return a.at_end();
    }

   private:
    friend class View;

    // Moves to the first trip of this level, from here on, whose child walk is not empty.
    UNISPH_HOST_DEVICE constexpr void descend() {
      if constexpr (has_child) {
        using ChildTraits = ContainerTraits<typename Child::container_type>;
        for (; !walk_.at_end(); walk_.advance()) {
          walk_.prefetch_step();
          child_ = child_prototype_
                       .rebind(walk_.holds_element() ? Traits::child(walk_.handle, walk_.cursor())
                                                     : ChildTraits::empty_handle())
                       .begin();
          if (!child_.at_end()) return;
        }
      }
    }

    // No [[no_unique_address]] on these members: with it, nvcc 13's device compiler (cicc) needed
    // over 20 GB for a kernel with one nested view.
    Walk walk_{};
    std::conditional_t<has_child, Child, NoChild> child_prototype_{};
    std::conditional_t<has_child, ChildIterator, NoChild> child_{};
  };

  UNISPH_HOST_DEVICE constexpr View() : fixed_trips_(fixed_trips()) {}
  // A view of `container` (anything that converts to its handle: a Frame&, a Supercell, ...).
  UNISPH_HOST_DEVICE constexpr View(const handle_type& container, Runtime runtime = Runtime{}, Child child = Child{},
                                    Collectivity group = Collectivity{})
      : handle_(container), runtime_(runtime), child_(child), group_(group), fixed_trips_(fixed_trips()) {}
  // A view without a container yet: the prototype of a Child level, which the parent view
  // points at each of its elements in turn (the seed writes PartInFrame(nullptr, runtime)).
  UNISPH_HOST_DEVICE constexpr View(std::nullptr_t, Runtime runtime = Runtime{}, Child child = Child{},
                                    Collectivity group = Collectivity{})
      : handle_(Traits::empty_handle()), runtime_(runtime), child_(child), group_(group), fixed_trips_(fixed_trips()) {}

  // The same view over another container of the same type.
  UNISPH_HOST_DEVICE constexpr View rebind(const handle_type& container) const {
    View other = *this;
    other.handle_ = container;
    return other;
  }

  UNISPH_HOST_DEVICE constexpr iterator begin() const {
    iterator it;
    it.walk_ = start();
    if constexpr (has_child) {
      it.child_prototype_ = child_;
      it.descend();
    }
    return it;
  }
  UNISPH_HOST_DEVICE constexpr std::default_sentinel_t end() const { return {}; }

  // The child views of this level, one per trip, as a range of ranges:
  //
  //   for (auto frame : view.children())   // the Child view over each element of this level
  //     for (auto slot : frame) ...         // the same slots, in the same order, as `for (auto slot : view)`
  //
  // Two loops the compilers see as nested, where the single iterator loop tests at every step
  // whether the level below ended (docs/views.md measures both). A padding position gives the
  // child view an empty container, as for_each does; its walk may still hold invalid slots (a
  // frame's N empty slots under a team).
  class child_iterator {
   public:
    using value_type = Child;
    using reference = Child;
    using difference_type = std::ptrdiff_t;
    using iterator_concept = std::forward_iterator_tag;
    using iterator_category = std::input_iterator_tag;

    child_iterator() = default;
    UNISPH_HOST_DEVICE constexpr Child operator*() const {
      using ChildTraits = ContainerTraits<typename Child::container_type>;
      walk_.prefetch_step();
      return prototype_.rebind(walk_.holds_element() ? Traits::child(walk_.handle, walk_.cursor())
                                                     : ChildTraits::empty_handle());
    }
    UNISPH_HOST_DEVICE constexpr child_iterator& operator++() {
      walk_.advance();
      return *this;
    }
    UNISPH_HOST_DEVICE constexpr child_iterator operator++(int) {
      child_iterator before = *this;
      walk_.advance();
      return before;
    }
    friend UNISPH_HOST_DEVICE constexpr bool operator==(const child_iterator& a, const child_iterator& b) {
      return a.walk_.position == b.walk_.position;
    }
    friend UNISPH_HOST_DEVICE constexpr bool operator==(const child_iterator& a, std::default_sentinel_t) {
      return a.walk_.at_end();
    }

   private:
    friend class View;
    Walk walk_{};
    Child prototype_{};
  };
  struct child_range : std::ranges::view_base {
    child_iterator first{};
    UNISPH_HOST_DEVICE constexpr child_iterator begin() const { return first; }
    UNISPH_HOST_DEVICE constexpr std::default_sentinel_t end() const { return {}; }
  };
  UNISPH_HOST_DEVICE constexpr child_range children() const {
    static_assert(has_child, "iter::View::children(): this view has no Child view; iterate it directly.");
    child_range r;
    r.first.walk_ = start();
    r.first.prototype_ = child_;
    return r;
  }

  // f(slot) for every slot the iterators visit, in the same order and with the same invalid
  // slots, but as one plain loop per level (the iterator's single loop has to test at every
  // step whether a level below ended, which compilers cannot split back into nested loops).
  template <class F>
  UNISPH_HOST_DEVICE constexpr void for_each(F&& f) const {
    if constexpr (!has_child && filled_in_one_block) {
      // Elements fill one block of slots (a frame's first `fill`): plain loops over the empty
      // positions before it (walking backward), the block itself without a test, and what follows.
      Walk walk = start();
      const Index filled = Traits::filled_prefix(handle_), slots = Traits::slot_count(handle_);
      const Index last = forward ? filled : slots;
      const Index stop = last < walk.count ? last : walk.count;
      if constexpr (!forward)
        for (; !walk.at_end() && walk.position < slots - filled; walk.advance()) f(slot_type());
      for (; walk.position < stop; walk.advance()) f(filled_slot(handle_, walk.cursor()));
      for (; !walk.at_end(); walk.advance()) f(slot_type());
    } else {
      for (Walk walk = start(); !walk.at_end(); walk.advance()) {
        walk.prefetch_step();
        if constexpr (dense && has_child) {
          child_.rebind(Traits::child(walk.handle, walk.cursor())).for_each(f);
        } else if constexpr (dense) {
          f(filled_slot(walk.handle, walk.cursor()));
        } else if constexpr (has_child) {
          using ChildTraits = ContainerTraits<typename Child::container_type>;
          child_.rebind(walk.holds_element() ? Traits::child(walk.handle, walk.cursor()) : ChildTraits::empty_handle())
              .for_each(f);
        } else {
          f(walk.holds_element() ? filled_slot(walk.handle, walk.cursor()) : slot_type());
        }
      }
    }
  }

  // g(child) for the Child view over each trip of this level (as children(), as one plain
  // loop): a walk that treats the lowest level's views as units (the rows of cells of a
  // neighbour search, each one contiguous range) chooses per unit how to walk it.
  template <class G>
  UNISPH_HOST_DEVICE constexpr void for_each_child(G&& g) const {
    static_assert(has_child, "iter::View::for_each_child(): this view has no Child view; use for_each().");
    using ChildTraits = ContainerTraits<typename Child::container_type>;
    for (Walk walk = start(); !walk.at_end(); walk.advance()) {
      if constexpr (dense)
        g(child_.rebind(Traits::child(walk.handle, walk.cursor())));
      else
        g(child_.rebind(walk.holds_element() ? Traits::child(walk.handle, walk.cursor()) : ChildTraits::empty_handle()));
    }
  }

  // The number of positions of this level the view considers (C above).
  UNISPH_HOST_DEVICE constexpr Index element_count() const {
    if constexpr (Traits::needs_runtime_size) {
      const Index size = Traits::size(handle_);
      const Index wanted = runtime_.get_element_count();
      return wanted < size ? wanted : size;
    } else {
      return Traits::number_of_elements;
    }
  }
  // The trips this worker makes at this level (the same for every worker of its group).
  UNISPH_HOST_DEVICE constexpr Index trips() const {
    const Walk walk = start();
    return walk.jump == 0 ? 0 : (walk.end_position - walk.position) / walk.jump;
  }

  UNISPH_HOST_DEVICE constexpr const handle_type& container() const { return handle_; }
  UNISPH_HOST_DEVICE constexpr const Runtime& runtime() const { return runtime_; }
  UNISPH_HOST_DEVICE constexpr const Child& child() const { return child_; }
  UNISPH_HOST_DEVICE constexpr const Collectivity& collectivity() const { return group_; }

 private:
  UNISPH_HOST_DEVICE constexpr Walk start() const {
    Walk walk;
    using Position = typename Walk::Position;
    walk.handle = handle_;
    const Index count = element_count();
    const Index jump = runtime_.get_jump() * group_.size();
    const Index offset = runtime_.get_offset() + group_.rank() * runtime_.get_jump();
    Index trips;
    if constexpr (Traits::needs_runtime_size && Walk::small)
      trips = small_trips_for(std::uint32_t(count), std::uint32_t(offset), std::uint32_t(jump));
    else if constexpr (Traits::needs_runtime_size)
      trips = trips_for(count, offset, jump);
    else
      trips = fixed_trips_;  // the same for every container of this type (a frame's N slots)
    walk.count = Position(count);
    walk.jump = Position(jump);
    walk.position = Position(offset);
    walk.end_position = Position(offset + trips * jump);
    if constexpr (Walk::filled_front) {
      const Index filled = Traits::filled_prefix(handle_);
      walk.filled_end = Position(filled < count ? filled : count);
    }
    if constexpr (!Walk::random_access)
      if (offset < walk.count) walk.stored_cursor = Traits::start(handle_, offset, forward);
    return walk;
  }

  // trips = ceil(C / j') - floor(o' / j') (0 once o' >= C rounded up to whole jumps). The divisions
  // are 32-bit where the values fit: a 64-bit division is a long subroutine on the GPU and
  // slower than a 32-bit one on most CPUs; these values nearly always fit.
  UNISPH_HOST_DEVICE static constexpr Index trips_for(Index count, Index offset, Index jump) {
    if (jump == 0) return 0;
    Index rounds, skipped;
    if (((count + jump) | offset) >> 32 == 0) {
      const std::uint32_t c = std::uint32_t(count), o = std::uint32_t(offset), j = std::uint32_t(jump);
      rounds = (c + j - 1) / j;  // ceil(C / j')
      skipped = o / j;           // floor(o' / j')
    } else {
      rounds = (count + jump - 1) / jump;
      skipped = offset / jump;
    }
    return skipped < rounds ? rounds - skipped : 0;
  }
  // The same for a level whose values always fit 32 bits (ContainerTraits::small_positions): no
  // test of the width, so that with a compile-time offset 0 and jump 1 the trip count folds to
  // the element count (the 64-bit test above stayed in the GPU code of every row of a neighbour walk).
  UNISPH_HOST_DEVICE static constexpr Index small_trips_for(std::uint32_t count, std::uint32_t offset, std::uint32_t jump) {
    if (jump == 0) return 0;
    const std::uint32_t rounds = (count + jump - 1) / jump, skipped = offset / jump;
    return skipped < rounds ? rounds - skipped : 0;
  }
  // Where the container fixes its element count at compile time, the trips depend only on the
  // runtime values and the group: computed once, when the view is made, not at every start()
  // (a child view starts once per element of its parent: per frame of a supercell).
  UNISPH_HOST_DEVICE constexpr Index fixed_trips() const {
    if constexpr (Traits::needs_runtime_size)
      return 0;
    else
      return trips_for(Traits::number_of_elements, runtime_.get_offset() + group_.rank() * runtime_.get_jump(),
                       runtime_.get_jump() * group_.size());
  }

  handle_type handle_{};
  Runtime runtime_{};
  Child child_{};
  Collectivity group_{};
  Index fixed_trips_ = 0;  // containers with a compile-time element count only
};

}  // namespace unisph::iter
