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
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>
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

  // For any walls: the box `start` (a domain) cut down around `seed` (a point of the water) so
  // that no wall particle lies within the margin of it. The wall particles are taken nearest the
  // seed first, and each one still near the box moves the face that separates it from the seed
  // along the axis where it lies farthest from the seed: a tank's floor cuts the bottom face, its
  // side walls the side faces, giving the tank's inside less the margin (of_tank's box); walls in
  // the water give a smaller box; a wall particle within the margin of the seed an empty one.
  static WallFreeBox around(const std::vector<Vec<T, D>>& wall, const Vec<T, D>& start_lower, const Vec<T, D>& start_upper,
                            const Vec<T, D>& seed, double cutoff) {
    const double margin = 1.01 * cutoff;
    double lo[D], hi[D];
    for (int a = 0; a < D; ++a) lo[a] = double(start_lower[a]) + margin, hi[a] = double(start_upper[a]) - margin;
    std::vector<std::pair<double, std::size_t>> order(wall.size());
    for (std::size_t k = 0; k < wall.size(); ++k) {
      double d = 0;
      for (int a = 0; a < D; ++a) d += (double(wall[k][a]) - double(seed[a])) * (double(wall[k][a]) - double(seed[a]));
      order[k] = {d, k};
    }
    std::sort(order.begin(), order.end());
    for (const auto& [distance, k] : order) {
      const Vec<T, D>& w = wall[k];
      bool near = true;
      for (int a = 0; a < D; ++a) near = near && double(w[a]) > lo[a] - margin && double(w[a]) < hi[a] + margin;
      if (!near) continue;
      int axis = 0;
      for (int a = 1; a < D; ++a)
        if (std::abs(double(w[a]) - double(seed[a])) > std::abs(double(w[axis]) - double(seed[axis]))) axis = a;
      if (!(std::abs(double(w[axis]) - double(seed[axis])) > margin)) return empty();  // a wall at the seed
      if (double(w[axis]) > double(seed[axis])) hi[axis] = std::min(hi[axis], double(w[axis]) - margin);
      else lo[axis] = std::max(lo[axis], double(w[axis]) + margin);
    }
    for (int a = 0; a < D; ++a)
      if (!(lo[a] < hi[a])) return empty();
    WallFreeBox box{};
    for (int a = 0; a < D; ++a) box.lower[a] = T(lo[a]), box.upper[a] = T(hi[a]);
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
