#pragma once
// A supercell: a doubly linked list of frames (frame.hpp) and the number of particles in its
// last frame; every other frame is full. The list lives in a pool of frames (one flat array)
// and is linked by indices, so the same supercell is valid in host and in device memory.
//
//   SupercellHeader   the stored part: first and last frame, frame count, fill of the last frame
//   Supercell<F>      what views walk: the header and the frame pool it indexes (F may be const)

#include <type_traits>

#include "unisph/core/config.hpp"
#include "unisph/iter/container_traits.hpp"
#include "unisph/iter/frame.hpp"

namespace unisph::iter {

struct SupercellHeader {
  Index first_frame;              // no_frame when the supercell is empty
  Index last_frame;               // no_frame when the supercell is empty
  Index frame_count;
  Index particles_in_last_frame;  // 0..N; the seed's nbElemsLastFrame

  UNISPH_HOST_DEVICE static constexpr SupercellHeader empty() { return {no_frame, no_frame, 0, 0}; }
};
static_assert(std::is_trivially_copyable_v<SupercellHeader> && std::is_trivially_default_constructible_v<SupercellHeader>);

template <class F>
struct Supercell {
  using frame_type = F;

  F* frames = nullptr;  // the pool the header's links index into
  SupercellHeader header = SupercellHeader::empty();

  // The number of particles: every frame but the last is full.
  UNISPH_HOST_DEVICE constexpr Index particle_count() const {
    return header.frame_count == 0 ? 0 : (header.frame_count - 1) * F::capacity + header.particles_in_last_frame;
  }
  // The particles used in the frame at pool index `frame`.
  UNISPH_HOST_DEVICE constexpr Index fill_of(Index frame) const {
    return frame == header.last_frame ? header.particles_in_last_frame : F::capacity;
  }
};

template <class F>
struct ContainerTraits<Supercell<F>> {
  using Handle = Supercell<F>;
  using Component = F;
  using ChildContainer = F;
  using Cursor = Index;  // pool index of a frame; no_frame past either end
  static constexpr bool needs_runtime_size = true;
  // A supercell's frame count fits 32 bits: its level is walked with 32-bit positions. With 64-bit
  // ones, nvcc kept fewer loads in flight in the particle loop of a thread walking a whole supercell
  // (views_bench all_particles/for_each on an H100: 1.80 times the hand loop; 0.98 with this).
  static constexpr bool small_positions = true;

  UNISPH_HOST_DEVICE static constexpr Handle empty_handle() { return Handle{}; }
  UNISPH_HOST_DEVICE static constexpr Index size(const Handle& h) { return h.header.frame_count; }
  // Following links is the only way along a list: k steps cost k loads. Views step only to
  // positions below the frame count, so the target frame exists and no test for the end of the
  // list is needed (with one, the strided benchmark ran 1.5 times slower than the hand loop).
  UNISPH_HOST_DEVICE static constexpr Cursor step(const Handle& h, Cursor frame, Index k, bool forward) {
    if (forward)
      for (; k > 0; --k) frame = h.frames[frame].next;
    else
      for (; k > 0; --k) frame = h.frames[frame].previous;
    return frame;
  }
  // The links of a frame (next and previous, side by side), fetched ahead while the work on the
  // frame goes on; the view's next step reads them. `frame` holds an element.
  UNISPH_ALWAYS_INLINE UNISPH_HOST_DEVICE static void prefetch_step(const Handle& h, Cursor frame) {
#if !UNISPH_DEVICE_CODE
    __builtin_prefetch(&h.frames[frame].next);
#else
    (void)h, (void)frame;
#endif
  }
  UNISPH_HOST_DEVICE static constexpr Cursor start(const Handle& h, Index position, bool forward) {
    return step(h, forward ? h.header.first_frame : h.header.last_frame, position, forward);
  }
  UNISPH_HOST_DEVICE static constexpr bool holds_element(const Handle&, Cursor frame) { return frame != no_frame; }
  UNISPH_HOST_DEVICE static constexpr F& element(const Handle& h, Cursor frame) { return h.frames[frame]; }
  UNISPH_HOST_DEVICE static constexpr FrameRef<F> child(const Handle& h, Cursor frame) {
    return FrameRef<F>(&h.frames[frame], h.fill_of(frame));
  }
};

}  // namespace unisph::iter
