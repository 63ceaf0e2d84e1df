#pragma once
// How a hierarchical view (iter::View) walks a container: one specialisation of
// ContainerTraits per container type, so that an algorithm written once over views runs over
// every container that has traits (the seed's "Trait Componenttyp hat Containertype
// Ausprägung"). Specialisations live next to their containers (frame.hpp, supercell.hpp,
// supercell_container.hpp).
//
// A specialisation provides, all static and UNISPH_HOST_DEVICE:
//   Handle                     trivially copyable; what a view stores to reach the container
//                              (pointers into one memory space and small values, never an owner)
//   Component                  what one slot holds (a particle for a frame, a frame for a supercell)
//   Cursor                     where an iterator stands
//   needs_runtime_size         the seed's NeedRuntimeSize: true when the number of elements is known
//                              only at run time (size(handle)); false when number_of_elements, a
//                              compile-time constant (the seed's NumberElements), gives it
//   empty_handle()             a handle to no container: all its slots are empty
//   start(h, position, forward) the cursor of the element at `position` in walking order
//   step(h, cursor, k, forward)  the cursor k elements further on (or an end cursor)
//   holds_element(h, cursor)   whether the slot holds an element (false for free slots)
//   element(h, cursor)         Component& of a slot that holds one (or slot(h, cursor), below)
// and, where views can nest below it, ChildContainer and child(h, cursor): the container one
// level down and its handle (ContainerTraits<ChildContainer>::Handle). Optional:
//   random_access              true where the cursor follows from the position (RandomAccessNavigation)
//   filled_prefix(h), slot_count(h)  where the elements fill the first filled_prefix of slot_count
//                              slots (a frame): View::for_each then walks them without a test
//   every_slot_filled          true where every slot holds an element (holds_element is always
//                              true): a walk without padding positions then tests no slot
//   small_positions            true where element counts always fit 32 bits: 32-bit positions
//   slot(h, cursor)            instead of element(): the slot of a filled position, a ValueSlot
//                              holding a value that names the element (slot_ref.hpp), for containers
//                              whose elements are places of a structure with nothing in memory to
//                              point at (a package of a mesh, a data point of a package:
//                              package_traits.hpp); the view then yields that slot type

#include <type_traits>

#include "unisph/core/config.hpp"

namespace unisph::iter {

// Declared, not defined: a container without a specialisation cannot be viewed.
template <class Container>
struct ContainerTraits;

template <class Container>
concept HasContainerTraits = requires { sizeof(ContainerTraits<Container>); };

// The seed's traits by their own names.
template <class Container>
using component_t = typename ContainerTraits<Container>::Component;
template <class Container>
inline constexpr bool needs_runtime_size_v = ContainerTraits<Container>::needs_runtime_size;

template <class Container>
concept ViewableContainer = HasContainerTraits<Container> && requires {
  typename ContainerTraits<Container>::Handle;
  typename ContainerTraits<Container>::Component;
  typename ContainerTraits<Container>::Cursor;
  { ContainerTraits<Container>::needs_runtime_size } -> std::convertible_to<bool>;
  { ContainerTraits<Container>::empty_handle() } -> std::same_as<typename ContainerTraits<Container>::Handle>;
};

template <class Container>
concept ContainerWithChildren = ViewableContainer<Container> && requires(
    const typename ContainerTraits<Container>::Handle& h, const typename ContainerTraits<Container>::Cursor& c) {
  ContainerTraits<Container>::child(h, c);
};

// Navigation shared by containers whose elements sit in one array: the cursor is an index.
struct RandomAccessNavigation {
  using Cursor = Index;
  // Views compute the cursor from the position instead of stepping it (one induction variable).
  static constexpr bool random_access = true;
  // Backward positions count from the last element (size - 1).
  UNISPH_HOST_DEVICE static constexpr Cursor start_at(Index size, Index position, bool forward) {
    return forward ? position : size - 1 - position;
  }
  // May leave the array (the view then no longer dereferences it: the position is past its count).
  UNISPH_HOST_DEVICE static constexpr Cursor step_by(Cursor cursor, Index k, bool forward) {
    return forward ? cursor + k : cursor - k;
  }
};

}  // namespace unisph::iter
