#pragma once
// NeighborPair<T, D>: what a kernel is given for each neighbour j of particle i.

#include <cmath>

#include "unisph/core/vector.hpp"

namespace unisph {

template <class T, int D>
struct NeighborPair {
  Vec<T, D> r_ij;      // x_i - x_j
  T squared_distance;  // |r_ij|^2, as the cutoff test computed it

  // |r_ij| and e_ij = r_ij / |r_ij| are computed when asked, so a kernel that needs only
  // r^2 pays for no square root. e_ij of coincident particles is the zero vector.
  UNISPH_HOST_DEVICE T distance() const { return std::sqrt(squared_distance); }
  UNISPH_HOST_DEVICE Vec<T, D> direction() const {
    const T r = distance();
    return r > T(0) ? r_ij * (T(1) / r) : Vec<T, D>{};
  }
};

}  // namespace unisph
