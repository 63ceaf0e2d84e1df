#pragma once
// Lattice seeding: the points origin + (n + 1/2) dx of a box that lie on one side of a level
// set's zero contour become particles, each of volume dx^D. Inside: a body's own particles;
// outside: the fluid around a body within the box.
//
//   LatticeSeeding<3, LevelSetSide<3>> seeding(lattice, LevelSetSide<3>{level_set.view(policy), true});
//   const Index n = seeding.count(policy);            // flags every lattice point, counts them
//   positions.resize(n); seeding.fill(policy, positions);   // in lattice order on every policy
//
// The side of a lattice point is decided by a functor: LevelSetSide (phi probed at the point: the
// level set's sign, closed even where the mesh leaks) or WindingNumberSide (the generalized
// winding number of the shape itself). The second is what `unisph generate` uses: the level set
// decides the side of cells away from its band by a flood fill from the grid border, which
// cannot reach a 2D hole (an enclosed region), so phi is negative there far from the hole's
// boundary (measured on plate_with_holes.poly: phi = -1.03 at the centre of a hole); the
// winding number is right everywhere, at the price of a BVH descent per lattice point. Points are numbered with
// axis 0 fastest and kept in that order (scan + scatter), so the particle set is the same on
// every policy and every run.

#include <cmath>
#include <cstdint>
#include <string>
#include <type_traits>

#include "unisph/core/error.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/levelset/multi_resolution_level_set_view.hpp"
#include "unisph/memory/discrete_variable.hpp"
#include "unisph/core/box.hpp"

namespace unisph {

enum class SeedRegion { inside, outside };

// The lattice of spacing dx filling a box: points at origin + (n + 1/2) dx, n < points per axis.
template <int D>
struct Lattice {
  Vec<Real, D> origin{};
  Vec<int, D> points{};
  Real spacing = Real(0);

  static Lattice covering(const Box<Real, D>& box, Real dx) {
    if (!(dx > Real(0))) throw Error("lattice: the spacing must be positive");
    Lattice l;
    l.origin = box.lower;
    l.spacing = dx;
    double total = 1;
    for (int k = 0; k < D; ++k) {
      const double n = std::floor(double(box.upper[k] - box.lower[k]) / double(dx) + 1e-9);
      if (!(n >= 1)) throw Error("lattice: the box is thinner than one spacing along axis " + std::to_string(k));
      l.points[k] = int(n);
      total *= n;
    }
    if (total >= 4.0e9)
      throw Error("lattice: " + std::to_string(total) + " points in the box; at most 4e9 (32-bit indices)");
    return l;
  }
  Index size() const {
    Index n = 1;
    for (int k = 0; k < D; ++k) n *= Index(points[k]);
    return n;
  }
  UNISPH_HOST_DEVICE Vec<Real, D> position(Index i) const {
    Vec<Real, D> x;
    for (int k = 0; k < D; ++k) {
      const Index n = i % Index(points[k]);
      i /= Index(points[k]);
      x[k] = origin[k] + (Real(n) + Real(0.5)) * spacing;
    }
    return x;
  }
};

// Particle side by the level set: phi < 0 inside, phi > 0 outside.
template <int D>
struct LevelSetSide {
  MultiResolutionLevelSetView<D> level_set;
  bool inside;
  UNISPH_HOST_DEVICE bool operator()(const Vec<Real, D>& x) const {
    const Real phi = level_set.probe_phi(x);
    return inside ? phi < Real(0) : phi > Real(0);
  }
};

// Particle side by the generalized winding number of a shape search view (inside where it
// exceeds 1/2).
template <class SearchView>
struct WindingNumberSide {
  SearchView search;
  bool inside;
  template <class Point>
  UNISPH_HOST_DEVICE bool operator()(const Point& x) const {
    return (search.winding_number(x) > Real(0.5)) == inside;
  }
};

namespace seeding_detail {

template <int D, class Side>
struct FlagLatticePoints {
  Lattice<D> lattice;
  Side side;
  View<std::uint32_t> flags;
  UNISPH_HOST_DEVICE void operator()(Index i) const { flags[i] = side(lattice.position(i)) ? 1u : 0u; }
};

struct TotalOfScan {
  View<const std::uint32_t> offsets;
  UNISPH_HOST_DEVICE Index operator()(Index) const { return Index(offsets[offsets.size() - 1]); }
};

template <int D>
struct ScatterLatticePoints {
  Lattice<D> lattice;
  View<const std::uint32_t> flags;
  View<const std::uint32_t> offsets;
  View<Vec<Real, D>> positions;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    if (flags[i]) positions[offsets[i]] = lattice.position(i);
  }
};

}  // namespace seeding_detail

// Side: LevelSetSide<D>, WindingNumberSide<...> or any trivially copyable functor x -> bool
// (true: a particle goes there) usable in kernels of the policy's memory space.
template <int D, class Side>
class LatticeSeeding {
 public:
  static_assert(std::is_trivially_copyable_v<Side>,
                "the side functor is captured by value into a kernel, so it must be trivially copyable.");
  LatticeSeeding(const Lattice<D>& lattice, const Side& side)
      : lattice_(lattice),
        side_(side),
        flags_("LatticeSeeding.Flags", lattice.size()),
        offsets_("LatticeSeeding.Offsets", lattice.size() + 1) {}

  // Flags the lattice points on the chosen side and returns how many there are. The level-set
  // view must be in the policy's memory space.
  template <ExecutionPolicy P>
  Index count(P policy) {
    particle_for(policy, lattice_.size(),
                 seeding_detail::FlagLatticePoints<D, Side>{lattice_, side_, flags_.write(policy)});
    exclusive_scan(policy, View<const std::uint32_t>(flags_.read(policy)), offsets_.write(policy));
    count_ = particle_reduce(policy, 1, Sum<Index>{}, seeding_detail::TotalOfScan{offsets_.read(policy)});
    return count_;
  }

  // Writes the flagged points, in lattice order, to positions[0, count).
  template <ExecutionPolicy P>
  void fill(P policy, DiscreteVariable<Vec<Real, D>>& positions) {
    if (positions.size() < count_)
      throw Error("lattice seeding: " + positions.describe() + " holds fewer than the " + std::to_string(count_) +
                  " seeded particles");
    particle_for(policy, lattice_.size(),
                 seeding_detail::ScatterLatticePoints<D>{lattice_, flags_.read(policy), offsets_.read(policy),
                                                         positions.read_write(policy)});
  }

 private:
  Lattice<D> lattice_;
  Side side_;
  DiscreteVariable<std::uint32_t> flags_;
  DiscreteVariable<std::uint32_t> offsets_;
  Index count_ = 0;
};

}  // namespace unisph
