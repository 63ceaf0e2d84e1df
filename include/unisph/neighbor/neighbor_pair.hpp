#pragma once
// NeighborPair<T, D>: what a kernel is given for each neighbour j of particle i — the pair's
// geometry, computed once when the pair is found: r_ij = x_i - x_j, |r_ij|^2, |r_ij| and
// e_ij = r_ij / |r_ij|.
//
// Stored neighbour lists keep one NeighborPair per pair (built at the relation's update()) and
// hand the kernel a reference to it, so a pass over stored lists loads no neighbour position
// and takes no square root or division: the geometry is that of the configuration at the last update, as
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
  Vec<T, D> e_ij;      // r_ij * (1 / |r_ij|); the zero vector for coincident particles

  // Fills |r_ij| and e_ij from r_ij and squared_distance (once the cutoff test accepted the
  // pair). A direct search calls it for every pair; what a kernel does not read is removed by
  // the compiler once the loop is inlined.
  UNISPH_HOST_DEVICE void complete() {
    r = std::sqrt(squared_distance);
    e_ij = r > T(0) ? r_ij * (T(1) / r) : Vec<T, D>{};
  }

  // As complete(), but on the device from one reciprocal square root (a special-function
  // instruction) instead of an IEEE square root and division: within an ulp or two of
  // complete()'s values there, the same bits on the host. For kernels that need agreement with
  // the host to round-off only, not bit for bit (the SPH relaxations: docs/sph.md, session 8;
  // particle relaxation keeps complete(), whose device results equal seq's bit for bit).
  UNISPH_HOST_DEVICE void complete_approximately() {
#if UNISPH_DEVICE_CODE
    const T inverse = squared_distance > T(0) ? T(rsqrt(squared_distance)) : T(0);
    r = squared_distance * inverse;
    e_ij = r_ij * inverse;
#else
    complete();
#endif
  }

  UNISPH_HOST_DEVICE T distance() const { return r; }
  UNISPH_HOST_DEVICE const Vec<T, D>& direction() const { return e_ij; }
};

}  // namespace unisph
