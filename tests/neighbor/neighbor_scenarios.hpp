#pragma once
// Particle layouts shared by the neighbour tests: each is a box, a cutoff and positions.

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "unisph/core/box.hpp"

namespace unisph::testing {

enum class Layout { random, lattice_on_faces, clustered, one_cell, one_particle, empty };

inline const char* to_string(Layout l) {
  switch (l) {
    case Layout::random: return "random";
    case Layout::lattice_on_faces: return "lattice on cell and box faces";
    case Layout::clustered: return "clustered (half in one cell)";
    case Layout::one_cell: return "all in one cell";
    case Layout::one_particle: return "one particle";
    case Layout::empty: return "no particles";
  }
  return "?";
}

inline constexpr Layout all_layouts[] = {Layout::random,   Layout::lattice_on_faces, Layout::clustered,
                                         Layout::one_cell, Layout::one_particle,     Layout::empty};

// The box [0, 1]^D with cutoff 1/8: 9 cells per axis, every face at a binary fraction, so a
// lattice of spacing 1/16 puts particles exactly on cell faces, on the box faces and at
// exactly the cutoff from each other.
template <class T, int D>
struct Scenario {
  Box<T, D> box{Vec<T, D>::constant(T(0)), Vec<T, D>::constant(T(1))};
  T cutoff = T(0.125);
  std::vector<Vec<T, D>> positions;
};

template <class T, int D>
Vec<T, D> random_point(std::mt19937_64& rng, T lo, T hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  Vec<T, D> x;
  for (int a = 0; a < D; ++a) x[a] = static_cast<T>(u(rng));
  return x;
}

template <class T, int D>
Scenario<T, D> make_scenario(Layout layout, unsigned seed = 7) {
  Scenario<T, D> s;
  std::mt19937_64 rng(seed + 31 * D + sizeof(T));
  const int n = D == 2 ? 500 : 900;
  switch (layout) {
    case Layout::random:
      for (int k = 0; k < n; ++k) s.positions.push_back(random_point<T, D>(rng, 0, 1));
      break;
    case Layout::lattice_on_faces: {
      const int per_axis = 17;  // 0, 1/16, ..., 1
      int total = 1;
      for (int a = 0; a < D; ++a) total *= per_axis;
      for (int k = 0; k < total; ++k) {
        Vec<T, D> x;
        int r = k;
        for (int a = 0; a < D; ++a, r /= per_axis) x[a] = T(r % per_axis) / T(16);
        s.positions.push_back(x);
      }
      break;
    }
    case Layout::clustered:
      for (int k = 0; k < n; ++k)
        s.positions.push_back(k % 2 ? random_point<T, D>(rng, 0.25, 0.37) : random_point<T, D>(rng, 0, 1));
      break;
    case Layout::one_cell:
      for (int k = 0; k < n / 3; ++k) s.positions.push_back(random_point<T, D>(rng, 0.5, 0.62));
      break;
    case Layout::one_particle:
      s.positions.push_back(random_point<T, D>(rng, 0, 1));
      break;
    case Layout::empty:
      break;
  }
  return s;
}

}  // namespace unisph::testing
