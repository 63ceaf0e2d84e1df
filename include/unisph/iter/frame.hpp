#pragma once
// A frame: N particle slots (N fixed at compile time) and the links that chain frames into a
// supercell (supercell.hpp). Frames live in one flat array (a DiscreteVariable of frames), and
// the links are indices into that array, not pointers, so the same bytes are valid in host
// and in device memory. A frame does not know how many of its slots are used; its supercell
// does (only its last frame may be partly filled), and a FrameRef carries that number.

#include <cstddef>
#include <type_traits>

#include "unisph/core/config.hpp"
#include "unisph/iter/container_traits.hpp"

namespace unisph::iter {

// The link value meaning "no frame" (before the first, after the last, an empty supercell).
inline constexpr Index no_frame = ~Index(0);

template <class Particle, Index N>
struct Frame {
  static_assert(N >= 1, "a frame holds at least one particle slot (N >= 1).");
  static_assert(std::is_trivially_copyable_v<Particle> && std::is_trivially_default_constructible_v<Particle>,
                "frames are copied between host and device memory byte for byte, so the particle type must be "
                "trivially copyable and trivially default constructible (a struct of numbers, without constructors).");

  using particle_type = Particle;
  static constexpr Index capacity = N;

  // No default member initializers: frames must stay trivially default constructible to live
  // in a DiscreteVariable; the supercell container sets the links when it chains a frame.
  Particle slots[N];
  Index previous;  // index of the previous frame of the same supercell, or no_frame
  Index next;      // index of the next frame of the same supercell, or no_frame
};

// A frame together with the number of its slots in use (slots [0, fill) hold particles).
// F is a Frame or a const Frame. A null frame has no particles: every slot is empty.
template <class F>
struct FrameRef {
  F* frame = nullptr;
  Index fill = 0;

  FrameRef() = default;
  UNISPH_HOST_DEVICE constexpr FrameRef(F* f, Index used) : frame(f), fill(f ? used : 0) {}
  // A frame on its own is taken as full (as in the seed's first example).
  UNISPH_HOST_DEVICE constexpr FrameRef(F& f) : frame(&f), fill(F::capacity) {}
  // A frame reference converts to a reference to a const frame.
  template <class G, class = std::enable_if_t<std::is_same_v<const G, F> && !std::is_same_v<G, F>>>
  UNISPH_HOST_DEVICE constexpr FrameRef(const FrameRef<G>& other) : frame(other.frame), fill(other.fill) {}
};

namespace detail {
template <class F>
struct FrameTraits : RandomAccessNavigation {
  using Handle = FrameRef<F>;
  using Component = std::conditional_t<std::is_const_v<F>, const typename F::particle_type, typename F::particle_type>;
  static constexpr bool needs_runtime_size = false;
  static constexpr Index number_of_elements = F::capacity;

  UNISPH_HOST_DEVICE static constexpr Handle empty_handle() { return Handle(nullptr, 0); }
  UNISPH_HOST_DEVICE static constexpr Cursor start(const Handle&, Index position, bool forward) {
    return start_at(F::capacity, position, forward);
  }
  UNISPH_HOST_DEVICE static constexpr Cursor step(const Handle&, Cursor cursor, Index k, bool forward) {
    return step_by(cursor, k, forward);
  }
  UNISPH_HOST_DEVICE static constexpr bool holds_element(const Handle& h, Cursor slot) { return slot < h.fill; }
  // The particles fill the first `fill` slots: View::for_each walks them without a test.
  UNISPH_HOST_DEVICE static constexpr Index filled_prefix(const Handle& h) { return h.fill; }
  UNISPH_HOST_DEVICE static constexpr Index slot_count(const Handle&) { return F::capacity; }
  UNISPH_HOST_DEVICE static constexpr Component& element(const Handle& h, Cursor slot) { return h.frame->slots[slot]; }
};
}  // namespace detail

template <class Particle, Index N>
struct ContainerTraits<Frame<Particle, N>> : detail::FrameTraits<Frame<Particle, N>> {};
template <class Particle, Index N>
struct ContainerTraits<const Frame<Particle, N>> : detail::FrameTraits<const Frame<Particle, N>> {};

}  // namespace unisph::iter
