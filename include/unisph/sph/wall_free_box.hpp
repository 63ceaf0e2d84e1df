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

  // For any walls: the box `start` (a domain) cut down, wall particle by wall particle, so that
  // none lies within the margin of it; each cut moves the one face that keeps the most volume.
  // A tank's walls give nearly of_tank's box; walls inside the domain give a smaller box (or an
  // empty one). The result depends on the order of `wall`, which is fixed at set-up.
  static WallFreeBox around(const std::vector<Vec<T, D>>& wall, const Vec<T, D>& start_lower, const Vec<T, D>& start_upper,
                            double cutoff) {
    const double margin = 1.01 * cutoff;
    double lo[D], hi[D];
    for (int a = 0; a < D; ++a) lo[a] = double(start_lower[a]) + margin, hi[a] = double(start_upper[a]) - margin;
    const auto volume = [&](const double* l, const double* h) {
      double v = 1;
      for (int a = 0; a < D; ++a) v *= std::max(0.0, h[a] - l[a]);
      return v;
    };
    for (const Vec<T, D>& w : wall) {
      bool near = true;
      for (int a = 0; a < D; ++a) near = near && double(w[a]) > lo[a] - margin && double(w[a]) < hi[a] + margin;
      if (!near) continue;
      int best_axis = 0;
      bool best_upper = false;
      double best = -1;
      for (int a = 0; a < D; ++a)
        for (int side = 0; side < 2; ++side) {
          double l[D], h[D];
          for (int b = 0; b < D; ++b) l[b] = lo[b], h[b] = hi[b];
          if (side == 0) l[a] = std::max(l[a], double(w[a]) + margin);
          else h[a] = std::min(h[a], double(w[a]) - margin);
          const double v = volume(l, h);
          if (v > best) best = v, best_axis = a, best_upper = side == 1;
        }
      if (best_upper) hi[best_axis] = std::min(hi[best_axis], double(w[best_axis]) - margin);
      else lo[best_axis] = std::max(lo[best_axis], double(w[best_axis]) + margin);
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
