#pragma once
// NeighborPair<T, D>: what a kernel is given for each neighbour j of particle i — the pair's
// geometry, computed once by the cutoff test: r_ij = x_i - x_j, |r_ij|^2 and |r_ij|.
//
// Stored neighbour lists keep one NeighborPair per pair (built at the relation's update()) and
// hand the kernel a reference to it, so a pass over stored lists loads no neighbour position
// and takes no square root: the geometry is that of the configuration at the last update, as
// in the dual-criteria time stepping of SPHinXsys (the configuration is updated once per
// advection step and reused by all its acoustic steps). A direct search computes it from the
// current positions at every pass.

#include <cmath>

#include "unisph/core/vector.hpp"

namespace unisph {

template <class T, int D>
struct NeighborPair {
  Vec<T, D> r_ij;      // x_i - x_j
  T squared_distance;  // |r_ij|^2, as the cutoff test computed it
  T r;                 // |r_ij| = sqrt(squared_distance)

  // Fills the distance from squared_distance (after the cutoff test accepted the pair).
  UNISPH_HOST_DEVICE void complete() { r = std::sqrt(squared_distance); }

  UNISPH_HOST_DEVICE T distance() const { return r; }
  // e_ij = r_ij / |r_ij|; the zero vector for coincident particles.
  UNISPH_HOST_DEVICE Vec<T, D> direction() const { return r > T(0) ? r_ij * (T(1) / r) : Vec<T, D>{}; }
};

}  // namespace unisph
