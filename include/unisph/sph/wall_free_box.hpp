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

  // What a wall particle may occupy: its position, or the box it sweeps where it moves
  // (motion/rigid_motion.hpp: swept_box).
  struct Extent {
    Vec<double, D> lower, upper;
  };

  // For any walls: the box `start` (a domain) cut down around `seed` (a point of the water) so
  // that no wall particle lies within the margin of it. The wall particles are taken nearest the
  // seed first, and each one still near the box moves the face that separates it from the seed
  // along the axis where it lies farthest from the seed: a tank's floor cuts the bottom face, its
  // side walls the side faces, giving the tank's inside less the margin (of_tank's box); walls in
  // the water give a smaller box; a wall particle within the margin of the seed an empty one.
  static WallFreeBox around(const std::vector<Vec<T, D>>& wall, const Vec<T, D>& start_lower, const Vec<T, D>& start_upper,
                            const Vec<T, D>& seed, double cutoff) {
    return around_extents(
        wall.size(),
        [&](std::size_t k) {
          Extent e;
          for (int a = 0; a < D; ++a) e.lower[a] = e.upper[a] = double(wall[k][a]);
          return e;
        },
        start_lower, start_upper, seed, cutoff);
  }
  // The same for extents: a moving wall particle's swept box is kept clear of as a whole (its
  // distance to the seed and along each axis is the box's nearest point's; a box that spans the
  // seed along every axis is within the margin of it). A point gives the result above.
  static WallFreeBox around(const std::vector<Extent>& wall, const Vec<T, D>& start_lower, const Vec<T, D>& start_upper,
                            const Vec<T, D>& seed, double cutoff) {
    return around_extents(
        wall.size(), [&](std::size_t k) { return wall[k]; }, start_lower, start_upper, seed, cutoff);
  }

 private:
  // Both: extent_of(k) gives wall particle k's extent (a point's made on the fly, so that a
  // large case's wall is not copied at start-up).
  template <class ExtentOf>
  static WallFreeBox around_extents(std::size_t count, const ExtentOf& extent_of, const Vec<T, D>& start_lower,
                                    const Vec<T, D>& start_upper, const Vec<T, D>& seed, double cutoff) {
    const double margin = 1.01 * cutoff, reach = (1 - 1e-9) * margin;
    double lo[D], hi[D];
    for (int a = 0; a < D; ++a) lo[a] = double(start_lower[a]) + margin, hi[a] = double(start_upper[a]) - margin;
    // Per axis, how far the extent lies beyond the seed (negative where it spans the seed).
    const auto beyond = [&](const Extent& w, int a) {
      return std::max(w.lower[a] - double(seed[a]), double(seed[a]) - w.upper[a]);
    };
    std::vector<std::pair<double, std::size_t>> order(count);
    for (std::size_t k = 0; k < count; ++k) {
      const Extent w = extent_of(k);
      double d = 0;
      for (int a = 0; a < D; ++a) d += std::max(beyond(w, a), 0.0) * std::max(beyond(w, a), 0.0);
      order[k] = {d, k};
    }
    std::sort(order.begin(), order.end());
    for (const auto& [distance, k] : order) {
      const Extent w = extent_of(k);
      // Near: within the margin of the box, less a rounding's worth (a wall particle in line with
      // one that cut a face lies exactly at the margin from it, and must not cut a second face).
      bool near = true;
      for (int a = 0; a < D; ++a) near = near && w.upper[a] > lo[a] - reach && w.lower[a] < hi[a] + reach;
      if (!near) continue;
      int axis = 0;
      for (int a = 1; a < D; ++a)
        if (beyond(w, a) > beyond(w, axis)) axis = a;
      if (!(beyond(w, axis) > margin)) return empty();  // a wall at the seed
      if (w.lower[axis] > double(seed[axis])) hi[axis] = std::min(hi[axis], w.lower[axis] - margin);
      else lo[axis] = std::max(lo[axis], w.upper[axis] + margin);
    }
    for (int a = 0; a < D; ++a)
      if (!(lo[a] < hi[a])) return empty();
    WallFreeBox box{};
    for (int a = 0; a < D; ++a) box.lower[a] = T(lo[a]), box.upper[a] = T(hi[a]);
    return box;
  }

 public:
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
