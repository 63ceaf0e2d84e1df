#pragma once
// A container of supercells: the frame pool and the supercell headers, each a DiscreteVariable,
// so the whole hierarchy is coherent between host and device memory like any other variable.
//
//   SupercellContainer<Particle, N>   owns the data; built on the host (add_supercell, push_back)
//   Supercells<F>                     what kernels and views hold: pointers into one memory space
//
//   SupercellContainer<Particle, 256> particles("electrons");
//   const Index cell = particles.add_supercell();
//   particles.push_back(cell, p);                       // a new frame whenever the last one is full
//   Supercells<Frame<Particle, 256>> all = particles.read_write(policy);   // for a kernel

#include <span>
#include <string>
#include <type_traits>

#include "unisph/core/error.hpp"
#include "unisph/exec/policy.hpp"
#include "unisph/iter/container_traits.hpp"
#include "unisph/iter/frame.hpp"
#include "unisph/iter/supercell.hpp"
#include "unisph/memory/discrete_variable.hpp"

namespace unisph::iter {

template <class F>
struct Supercells {
  using frame_type = F;
  using header_type = std::conditional_t<std::is_const_v<F>, const SupercellHeader, SupercellHeader>;

  F* frames = nullptr;
  header_type* headers = nullptr;
  Index count = 0;

  UNISPH_HOST_DEVICE constexpr Index size() const { return count; }
  UNISPH_HOST_DEVICE constexpr Supercell<F> operator[](Index i) const { return {frames, headers[i]}; }
};

// Views over a container of supercells visit the headers; one level down, a view over
// Supercell<F> walks the frames of the supercell at hand.
template <class F>
struct ContainerTraits<Supercells<F>> : RandomAccessNavigation {
  using Handle = Supercells<F>;
  using Component = typename Supercells<F>::header_type;
  using ChildContainer = Supercell<F>;
  static constexpr bool needs_runtime_size = true;

  UNISPH_HOST_DEVICE static constexpr Handle empty_handle() { return Handle{}; }
  UNISPH_HOST_DEVICE static constexpr Index size(const Handle& h) { return h.count; }
  UNISPH_HOST_DEVICE static constexpr Cursor start(const Handle& h, Index position, bool forward) {
    return start_at(h.count, position, forward);
  }
  UNISPH_HOST_DEVICE static constexpr Cursor step(const Handle&, Cursor cursor, Index k, bool forward) {
    return step_by(cursor, k, forward);
  }
  UNISPH_HOST_DEVICE static constexpr bool holds_element(const Handle&, Cursor) { return true; }
  UNISPH_HOST_DEVICE static constexpr Component& element(const Handle& h, Cursor i) { return h.headers[i]; }
  UNISPH_HOST_DEVICE static constexpr Supercell<F> child(const Handle& h, Cursor i) { return h[i]; }
};

template <class Particle, Index N>
class SupercellContainer {
 public:
  using frame_type = Frame<Particle, N>;

  explicit SupercellContainer(const std::string& name, Index supercell_count = 0)
      : frames_(name + ".frames"), headers_(name + ".supercells") {
    add_supercells(supercell_count);
  }

  Index supercell_count() const { return headers_.size(); }
  Index frame_count() const { return frames_used_; }

  // Appends `count` empty supercells; returns the index of the first.
  Index add_supercells(Index count) {
    const Index first = headers_.size();
    headers_.resize(first + count);
    unisph::View<SupercellHeader> headers = headers_.read_write(MemorySpace::host);
    for (Index i = first; i < first + count; ++i) headers[i] = SupercellHeader::empty();
    return first;
  }
  Index add_supercell() { return add_supercells(1); }

  // Appends particles to a supercell, filling its last frame and chaining new frames to it.
  void append(Index supercell, std::span<const Particle> particles) {
    check_supercell(supercell);
    Index new_frames = 0;
    {
      const SupercellHeader h = headers_.read(MemorySpace::host)[supercell];
      const Index room = h.frame_count == 0 ? 0 : N - h.particles_in_last_frame;
      if (particles.size() > room) new_frames = (particles.size() - room + N - 1) / N;
    }
    reserve_frames(frames_used_ + new_frames);
    unisph::View<frame_type> frames = frames_.read_write(MemorySpace::host);
    SupercellHeader& h = headers_.read_write(MemorySpace::host)[supercell];
    for (const Particle& p : particles) {
      if (h.frame_count == 0 || h.particles_in_last_frame == N) chain_new_frame(frames, h);
      frames[h.last_frame].slots[h.particles_in_last_frame++] = p;
    }
  }
  void push_back(Index supercell, const Particle& particle) { append(supercell, std::span<const Particle>(&particle, 1)); }

  // Chains one frame with no particles to a supercell (a supercell may end in an empty frame,
  // for instance after particles left it).
  void append_empty_frame(Index supercell) {
    check_supercell(supercell);
    reserve_frames(frames_used_ + 1);
    unisph::View<frame_type> frames = frames_.read_write(MemorySpace::host);
    chain_new_frame(frames, headers_.read_write(MemorySpace::host)[supercell]);
  }

  // Views of the whole hierarchy in a policy's memory space (coherent like any variable access).
  template <ExecutionPolicy P>
  Supercells<frame_type> read_write(P) {
    return {frames_.read_write(P::space).data(), headers_.read_write(P::space).data(), headers_.size()};
  }
  template <ExecutionPolicy P>
  Supercells<const frame_type> read(P) {
    return {frames_.read(P::space).data(), headers_.read(P::space).data(), headers_.size()};
  }
  Supercells<frame_type> read_write(MemorySpace space) {
    return {frames_.read_write(space).data(), headers_.read_write(space).data(), headers_.size()};
  }
  Supercells<const frame_type> read(MemorySpace space) {
    return {frames_.read(space).data(), headers_.read(space).data(), headers_.size()};
  }

  DiscreteVariable<frame_type>& frames() { return frames_; }
  DiscreteVariable<SupercellHeader>& headers() { return headers_; }

 private:
  void check_supercell(Index supercell) const {
    if (supercell >= headers_.size())
      throw Error("SupercellContainer '" + headers_.name() + "': supercell " + std::to_string(supercell) +
                  " does not exist (there are " + std::to_string(headers_.size()) + ")");
  }
  void reserve_frames(Index needed) {
    if (needed <= frames_.size()) return;
    Index capacity = frames_.size() < 4 ? 4 : frames_.size();
    while (capacity < needed) capacity *= 2;
    frames_.resize(capacity);
  }
  void chain_new_frame(unisph::View<frame_type> frames, SupercellHeader& h) {
    const Index f = frames_used_++;
    frames[f].previous = h.last_frame;
    frames[f].next = no_frame;
    if (h.frame_count == 0)
      h.first_frame = f;
    else
      frames[h.last_frame].next = f;
    h.last_frame = f;
    ++h.frame_count;
    h.particles_in_last_frame = 0;
  }

  DiscreteVariable<frame_type> frames_;
  DiscreteVariable<SupercellHeader> headers_;
  Index frames_used_ = 0;
};

}  // namespace unisph::iter
