#pragma once
// PeriodicImages<T, D>: periodic boundaries for the neighbour search, as ghost images.
//
// For a particle set in a box [lower, upper] that is periodic along some of its axes, the
// owned particles within the ghost width (the cutoff, padded for rounding: ghost_width()) of a
// periodic face get copies in the set's ghost slots, shifted by +-L (L = upper - lower) along
// that axis; a particle near k periodic faces gets 2^k - 1 images (the faces, the edges and the
// corner). The cell linked list and the relations then see owned particles and images alike as
// targets, and a direct search, stored lists or a contact relation find the minimum-image
// neighbours without knowing the domain is periodic. Per step a solver calls
//
//   images.wrap(policy);      // owned particles that left the box across a periodic axis come back in
//   images.build(policy);     // which images exist (ghost count, source, image code) and their positions
//   cells.build(policy);      // a cell list over owned + ghost particles, box = images.search_box()
//   relation.update(policy);  // (relation.set_source_count(set.owned_count()) once)
//   ...
//   images.refresh(policy, velocity, density, ...);   // before every interaction pass that reads
//                                                     // them, after the owned values changed
//
// build() orders the images by their source's index, then by image code (deterministic, the
// same on every policy): ghost g (slot owned_count() + g) is the image of owned particle
// sources()[g], shifted by the code codes()[g] = sum_a d_a 3^a, d_a = 0 (no shift along axis a),
// 1 (+L_a: the source is near the lower face) or 2 (-L_a: near the upper face). An image gets
// its source's id ("ParticleId") too.
//
// The ghost slots are the images': set_ghost_count() is called with their number (which
// resizes every variable of the set when the number changes: see docs/neighbor_search.md,
// "Periodic boundaries"). A sort of the owned particles (ParticleSorter) makes sources() stale:
// build again after it. Every variable a relation's kernels read at j must be refreshed before
// the pass; positions are refreshed by every refresh() (with the shift), and by build().

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <string>
#include <string_view>

#include "unisph/core/box.hpp"
#include "unisph/core/error.hpp"
#include "unisph/core/uncontracted_arithmetic.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/exec/reduce_ops.hpp"
#include "unisph/memory/discrete_variable.hpp"
#include "unisph/particles/particle_set.hpp"

namespace unisph {

namespace periodic_detail {

// The powers of 3 below 3^D: image code digit a has weight 3^a.
template <int D>
UNISPH_HOST_DEVICE constexpr unsigned image_code_count() {
  unsigned n = 1;
  for (int a = 0; a < D; ++a) n *= 3u;
  return n;
}

// What a kernel needs to know about the domain.
template <class T, int D>
struct PeriodicDomain {
  Vec<T, D> lower;
  Vec<T, D> upper;
  Vec<T, D> length;  // upper - lower
  unsigned periodic; // bit a: axis a is periodic
  T width;           // ghost width: images of particles closer than this to a periodic face

  UNISPH_HOST_DEVICE bool is_periodic(int a) const { return (periodic >> a) & 1u; }

  // Which shifts particle x may take along axis a: bit 0 +L (near the lower face), bit 1 -L
  // (near the upper face); both only where the bands overlap (L < 2 width, which needs a
  // width padded beyond the cutoff: at most one of the two is then within the cutoff of
  // anything, since L >= 2 cutoff). A NaN coordinate takes none.
  UNISPH_HOST_DEVICE unsigned shifts_along(const Vec<T, D>& x, int a) const {
    if (!is_periodic(a)) return 0u;
    unsigned s = 0u;
    if (uncontracted::sub(x[a], lower[a]) < width) s |= 1u;
    if (uncontracted::sub(upper[a], x[a]) < width) s |= 2u;
    return s;
  }

  // True when image `code` (1 .. 3^D - 1) of x exists: each digit is 0 or an allowed shift.
  UNISPH_HOST_DEVICE bool has_image(const unsigned (&allowed)[D], unsigned code) const {
    for (int a = 0; a < D; ++a, code /= 3u) {
      const unsigned d = code % 3u;
      if (d != 0u && !(allowed[a] & d)) return false;
    }
    return true;
  }

  // x shifted by image `code` (the same bits wherever it is computed: one add or subtract).
  UNISPH_HOST_DEVICE Vec<T, D> shifted(Vec<T, D> x, unsigned code) const {
    for (int a = 0; a < D; ++a, code /= 3u) {
      const unsigned d = code % 3u;
      if (d == 1u) x[a] = uncontracted::add(x[a], length[a]);
      if (d == 2u) x[a] = uncontracted::sub(x[a], length[a]);
    }
    return x;
  }

  template <class F>
  UNISPH_HOST_DEVICE void for_each_image(const Vec<T, D>& x, F&& f) const {
    unsigned allowed[D];
    unsigned any = 0u;
    for (int a = 0; a < D; ++a) {
      allowed[a] = shifts_along(x, a);
      any |= allowed[a];
    }
    if (any == 0u) return;
    for (unsigned code = 1; code < image_code_count<D>(); ++code)
      if (has_image(allowed, code)) f(code);
  }
};

// x -= L floor((x - lower) / L) along each periodic axis, for owned particles outside the box;
// particles inside (faces included) are left bit for bit. Rounding may leave the result a few
// ulps outside: one more +-L brings it in (x == upper is inside: the box is closed). A
// non-finite coordinate is left as it is (the cell list reports it).
template <class T, int D>
struct WrapIntoBox {
  PeriodicDomain<T, D> domain;
  View<Vec<T, D>> positions;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    Vec<T, D> x = positions[i];
    bool moved = false;
    for (int a = 0; a < D; ++a) {
      if (!domain.is_periodic(a)) continue;
      T xa = x[a];
      if (!(xa < domain.lower[a] || xa > domain.upper[a])) continue;  // inside, or NaN
      if (!(xa - xa == T(0))) continue;                                // infinite
      const T turns = std::floor(uncontracted::sub(xa, domain.lower[a]) / domain.length[a]);
      xa = uncontracted::sub(xa, uncontracted::mul(domain.length[a], turns));
      if (xa < domain.lower[a]) xa = uncontracted::add(xa, domain.length[a]);
      if (xa > domain.upper[a]) xa = uncontracted::sub(xa, domain.length[a]);
      x[a] = xa;
      moved = true;
    }
    if (moved) positions[i] = x;
  }
};

// counts[i] = the number of images of owned particle i.
template <class T, int D>
struct CountImages {
  PeriodicDomain<T, D> domain;
  View<const Vec<T, D>> positions;
  View<std::uint32_t> counts;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    std::uint32_t n = 0;
    domain.for_each_image(positions[i], [&](unsigned) { ++n; });
    counts[i] = n;
  }
};

// The total of the scan (its last element), read through a one-item reduction.
struct LastOffset {
  View<const std::uint32_t> offsets;
  UNISPH_HOST_DEVICE std::uint64_t operator()(Index) const { return offsets[offsets.size() - 1]; }
};

// Writes owned particle i's images from slot offsets[i] on, in ascending image code.
template <class T, int D>
struct FillImages {
  PeriodicDomain<T, D> domain;
  View<const std::uint32_t> offsets;
  View<Vec<T, D>> positions;  // owned + ghosts
  View<std::uint32_t> sources;
  View<std::uint32_t> codes;
  Index owned;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    const Vec<T, D> x = positions[i];
    Index g = offsets[i];
    domain.for_each_image(x, [&](unsigned code) {
      sources[g] = static_cast<std::uint32_t>(i);
      codes[g] = code;
      positions[owned + g] = domain.shifted(x, code);
      ++g;
    });
  }
};

// Ghost g's position from its source's current one.
template <class T, int D>
struct RefreshImagePositions {
  PeriodicDomain<T, D> domain;
  View<const std::uint32_t> sources;
  View<const std::uint32_t> codes;
  View<Vec<T, D>> positions;
  Index owned;
  UNISPH_HOST_DEVICE void operator()(Index g) const {
    positions[owned + g] = domain.shifted(positions[sources[g]], codes[g]);
  }
};

// Ghost g's value is its source's.
template <class V>
struct CopyToImages {
  View<const std::uint32_t> sources;
  View<V> values;
  Index owned;
  UNISPH_HOST_DEVICE void operator()(Index g) const { values[owned + g] = values[sources[g]]; }
};

// The same for a variable known by name only: `words` words of its element per particle.
template <class Word>
struct CopyBytesToImages {
  View<const std::uint32_t> sources;
  Word* data;
  Index words;
  Index owned;
  UNISPH_HOST_DEVICE void operator()(Index g) const {
    const Word* from = data + static_cast<Index>(sources[g]) * words;
    Word* to = data + (owned + g) * words;
    for (Index w = 0; w < words; ++w) to[w] = from[w];
  }
};

}  // namespace periodic_detail

template <class T, int D>
class PeriodicImages {
 public:
  using Position = Vec<T, D>;

  // Images of `particles` (whose registered variable `positions` they shift) in `box`, periodic
  // along the axes a with periodic[a], for a search with `cutoff`. Throws unisph::Error (one
  // line) when the box is empty or not finite, the cutoff is not positive, or the box is
  // narrower than two cutoffs along a periodic axis (the images would be wider than the domain).
  PeriodicImages(ParticleSet& particles, DiscreteVariable<Position>& positions, const Box<T, D>& box,
                 const std::array<bool, D>& periodic, T cutoff)
      : particles_(particles),
        positions_(positions),
        offsets_(particles.name() + ".ImageOffsets"),
        sources_(particles.name() + ".ImageSources"),
        codes_(particles.name() + ".ImageCodes") {
    const std::string who = "PeriodicImages of '" + particles.name() + "': ";
    if (!(cutoff > T(0)) || !(cutoff < std::numeric_limits<T>::infinity()))
      throw Error(who + "the cutoff is " + std::to_string(cutoff) + "; it must be positive and finite");
    domain_.lower = box.lower;
    domain_.upper = box.upper;
    domain_.periodic = 0u;
    T largest = cutoff;
    for (int a = 0; a < D; ++a) {
      const T length = box.upper[a] - box.lower[a];
      if (!(length > T(0)) || !(length < std::numeric_limits<T>::infinity()))
        throw Error(who + "the box " + to_string(box) + " is empty or not finite along axis " + std::to_string(a));
      domain_.length[a] = length;
      if (periodic[a]) {
        domain_.periodic |= 1u << a;
        if (!(length >= T(2) * cutoff))
          throw Error(who + "the box " + to_string(box) + " is " + std::to_string(length) +
                      " wide along periodic axis " + std::to_string(a) + ", narrower than two cutoffs (2 x " +
                      std::to_string(cutoff) + "): ghost images would be wider than the domain");
      }
      largest = std::max({largest, std::abs(box.lower[a]), std::abs(box.upper[a])});
    }
    cutoff_ = cutoff;
    // The cutoff padded so that rounding in an image's position (x + L) or in r_ij can never
    // make a pair pass the cutoff test whose image was not made: a relative 1e-4 plus 16 ulps
    // of the largest coordinate. Extra images beyond the cutoff are found by no pair test.
    domain_.width = cutoff * T(1.0001) + T(16) * largest * std::numeric_limits<T>::epsilon();
    // The search box reaches a little beyond the widest image (x + L rounds up by an ulp at most).
    search_margin_ = domain_.width + T(16) * largest * std::numeric_limits<T>::epsilon();
  }

  Box<T, D> box() const { return {domain_.lower, domain_.upper}; }
  bool periodic(int axis) const { return domain_.is_periodic(axis); }
  unsigned periodic_axes() const { return domain_.periodic; }
  T cutoff() const { return cutoff_; }
  // Images are made of particles closer than this to a periodic face (the cutoff, padded).
  T ghost_width() const { return domain_.width; }

  // The box a cell list over owned particles and images must cover: the domain, extended beyond
  // both faces of every periodic axis by the ghost width and a few ulps (images lie there). Other
  // axes are the domain's.
  Box<T, D> search_box() const {
    Box<T, D> b{domain_.lower, domain_.upper};
    for (int a = 0; a < D; ++a)
      if (domain_.is_periodic(a)) {
        b.lower[a] = domain_.lower[a] - search_margin_;
        b.upper[a] = domain_.upper[a] + search_margin_;
      }
    return b;
  }

  // Moves owned particles that left the box across a periodic axis back in. Asynchronous on
  // the device.
  template <ExecutionPolicy P>
  void wrap(P policy) {
    check_positions();
    if (domain_.periodic == 0u || particles_.owned_count() == 0) return;
    particle_for(policy, particles_.owned_count(),
                 periodic_detail::WrapIntoBox<T, D>{domain_, positions_.read_write(policy)});
  }

  // Makes the images of the owned particles' current positions: counts (a kernel), offsets (a
  // scan), the total (read back: the host sets the ghost count, so this waits on the device),
  // then sources, codes and positions (a kernel). Ghost count = image count afterwards.
  template <ExecutionPolicy P>
  void build(P policy) {
    check_positions();
    const Index owned = particles_.owned_count();
    Index total = 0;
    if (domain_.periodic != 0u && owned > 0) {
      offsets_.resize(owned + 1);
      View<std::uint32_t> offsets = offsets_.write(policy);
      particle_for(policy, owned,
                   periodic_detail::CountImages<T, D>{domain_, positions_.read(policy), offsets});
      exclusive_scan(policy, View<const std::uint32_t>(offsets.subview(0, owned)), offsets);
      total = Index(particle_reduce(policy, 1, Sum<std::uint64_t>{},
                                    periodic_detail::LastOffset{offsets_.read(policy)}));
    }
    if (owned + total >= Index(std::numeric_limits<std::uint32_t>::max()))
      throw Error("PeriodicImages of '" + particles_.name() + "': " + std::to_string(owned) + " particles and " +
                  std::to_string(total) + " images; particle indices are 32-bit");
    if (total != particles_.ghost_count()) particles_.set_ghost_count(total);
    check_positions();
    sources_.resize(total);
    codes_.resize(total);
    if (total > 0) {
      particle_for(policy, owned,
                   periodic_detail::FillImages<T, D>{domain_, offsets_.read(policy), positions_.read_write(policy),
                                                     sources_.write(policy), codes_.write(policy), owned});
      // An image carries its source's id, as a ghost from another rank carries its owner's: a
      // cell list ordered by id (CellLinkedList::order_within_cells_by_id) places it by that id.
      particle_for(policy, total,
                   periodic_detail::CopyToImages<std::uint64_t>{sources_.read(policy),
                                                                particles_.ids().read_write(policy), owned});
    }
    ++builds_;
  }

  // Copies the owned values to the images: the positions (shifted) and each of `variables`
  // (variables of the set, total_count() elements; the positions may be among them). Call after
  // the owned values changed and before a pass that reads them at neighbours. Asynchronous.
  template <ExecutionPolicy P, class... V>
  void refresh(P policy, DiscreteVariable<V>&... variables) {
    refresh_positions(policy);
    (refresh_one(policy, variables), ...);
  }

  // The same for variables of the set named in `names` (any element type: copied as bytes).
  template <ExecutionPolicy P>
  void refresh(P policy, std::initializer_list<std::string_view> names) {
    refresh_positions(policy);
    for (std::string_view name : names) refresh_named(policy, name);
  }

  // Only the positions: ghost g = its source's position + its shift.
  template <ExecutionPolicy P>
  void refresh_positions(P policy) {
    check_built();
    if (ghost_count() == 0) return;
    particle_for(policy, ghost_count(),
                 periodic_detail::RefreshImagePositions<T, D>{domain_, sources_.read(policy), codes_.read(policy),
                                                              positions_.read_write(policy),
                                                              particles_.owned_count()});
  }

  // A variable of the set known by name (bytes; 4-byte words where the element size allows).
  template <ExecutionPolicy P>
  void refresh_named(P policy, std::string_view name) {
    check_built();
    VariableBase& v = *particles_.variables().entry(name).variable;
    if (&v == static_cast<VariableBase*>(&positions_)) return refresh_positions(policy);
    check_size(v);
    if (ghost_count() == 0) return;
    void* data = v.prepare(P::space, Access::read_write);
    const Index owned = particles_.owned_count();
    if (v.element_size() % 4 == 0) {
      using W = std::uint32_t;
      particle_for(policy, ghost_count(),
                   periodic_detail::CopyBytesToImages<W>{sources_.read(policy), static_cast<W*>(data),
                                                         Index(v.element_size() / 4), owned});
    } else {
      using W = unsigned char;
      particle_for(policy, ghost_count(),
                   periodic_detail::CopyBytesToImages<W>{sources_.read(policy), static_cast<W*>(data),
                                                         Index(v.element_size()), owned});
    }
  }

  Index ghost_count() const { return sources_.size(); }
  // Ghost g (slot owned_count() + g) is the image of owned particle sources()[g] ...
  DiscreteVariable<std::uint32_t>& sources() { return sources_; }
  // ... shifted by image code codes()[g] (see the header comment).
  DiscreteVariable<std::uint32_t>& codes() { return codes_; }
  // The shift of an image code: x_image = x_source + shift(code).
  Position shift(unsigned code) const { return domain_.shifted(Position::constant(T(0)), code); }
  // How many times build() ran.
  std::uint64_t builds() const { return builds_; }

 private:
  template <ExecutionPolicy P, class V>
  void refresh_one(P policy, DiscreteVariable<V>& v) {
    if (static_cast<VariableBase*>(&v) == static_cast<VariableBase*>(&positions_)) return;  // done
    check_size(v);
    if (ghost_count() == 0) return;
    particle_for(policy, ghost_count(),
                 periodic_detail::CopyToImages<V>{sources_.read(policy), v.read_write(policy),
                                                  particles_.owned_count()});
  }

  void check_positions() const {
    if (positions_.size() != particles_.total_count())
      throw Error("PeriodicImages of '" + particles_.name() + "': the positions " + positions_.describe() +
                  " are not the set's (" + std::to_string(particles_.total_count()) +
                  " particles); pass the variable registered in the particle set");
  }
  void check_built() const {
    if (builds_ == 0 && particles_.ghost_count() != 0)
      throw Error("PeriodicImages of '" + particles_.name() + "': refresh before build");
    if (particles_.ghost_count() != ghost_count())
      throw Error("PeriodicImages of '" + particles_.name() + "': the set has " +
                  std::to_string(particles_.ghost_count()) + " ghosts but " + std::to_string(ghost_count()) +
                  " images were built; call build() again");
  }
  void check_size(const VariableBase& v) const {
    if (v.size() != particles_.total_count())
      throw Error("PeriodicImages of '" + particles_.name() + "': " + v.describe() +
                  " is not a variable of the set (" + std::to_string(particles_.total_count()) + " particles)");
  }

  ParticleSet& particles_;
  DiscreteVariable<Position>& positions_;
  periodic_detail::PeriodicDomain<T, D> domain_{};
  T cutoff_ = T(0);
  T search_margin_ = T(0);
  DiscreteVariable<std::uint32_t> offsets_;
  DiscreteVariable<std::uint32_t> sources_;
  DiscreteVariable<std::uint32_t> codes_;
  std::uint64_t builds_ = 0;
};

}  // namespace unisph
