#pragma once
// The box of a tank whose points are farther than the cutoff from every wall particle: a fluid
// particle inside it has no wall neighbour, so with a direct search (which tests the current
// positions) the pressure and density relaxations skip its walk over the wall's cells (about
// 21 rows of cells of half the cutoff in 3D, all empty in the bulk of the water) without
// changing a bit of the result. Stored lists keep the pairs of the last build, which a particle
// that has moved into the box since still has: they are always walked. The tank's wall particles lie
// outside the open box (0, tank) (tank_particles.hpp), so the box is [m, tank - m] per axis
// with m the cutoff and a 1 % margin that covers the rounding of the pair test; it is checked
// against the wall particles and left empty if one lies inside (0, tank).
#include <cstddef>
#include <limits>
#include <vector>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"

namespace unisph::sph {

template <class T, int D>
struct WallFreeBox {
  Vec<T, D> lower, upper;

  // False for a non-finite x (the walk then reports nothing, as before).
  UNISPH_HOST_DEVICE bool contains(const Vec<T, D>& x) const {
    bool inside = true;
    for (int a = 0; a < D; ++a) inside = inside && x[a] >= lower[a] && x[a] <= upper[a];
    return inside;
  }

  static WallFreeBox empty() {
    WallFreeBox box{};
    for (int a = 0; a < D; ++a) {
      box.lower[a] = std::numeric_limits<T>::infinity();
      box.upper[a] = -std::numeric_limits<T>::infinity();
    }
    return box;
  }

  static WallFreeBox of_tank(const std::vector<double>& tank, const std::vector<Vec<T, D>>& wall, double cutoff) {
    for (const Vec<T, D>& w : wall) {
      bool outside = false;
      for (int a = 0; a < D; ++a) outside = outside || double(w[a]) <= 0.0 || double(w[a]) >= tank[a];
      if (!outside) return empty();
    }
    const double margin = 1.01 * cutoff;
    WallFreeBox box{};
    for (int a = 0; a < D; ++a) {
      box.lower[a] = T(margin);
      box.upper[a] = T(tank[a] - margin);
    }
    return box;
  }
};

}  // namespace unisph::sph
