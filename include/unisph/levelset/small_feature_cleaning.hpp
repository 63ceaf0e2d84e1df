#pragma once
// Small-feature cleaning of the finest layer (the idea of Yu et al. 2023, re-distancing near
// features the data spacing does not resolve; our own formulation):
//
// 1. Mark. A data point is resolved when |phi| >= 0.45 dx. A point with |phi| < 0.45 dx (near
//    the surface) lies on a resolved surface when its 3^D neighbourhood holds resolved points of
//    both signs: next to a flat wall the diagonal neighbour towards each side is at least one
//    spacing farther from it (|n|_1 >= 1), so both exist, with 0.1 dx to spare (0.45, not 0.5:
//    walls that lie half-way between lattice planes give |phi| = dx / 2 to round-off, and a
//    threshold there would decide by the last bit). Where one side is missing, the point belongs to
//    a feature thinner than about one spacing (a fin, a thin gap): it is removed and takes the
//    side that is present (outside when neither is).
// 2. Sample the kept surface. Every kept point with |phi| < dx records its foot x - phi n
//    and the normal there, where phi is linear along every axis (away from edges and ridges of
//    the distance, where the normal is not accurate): a tangent disk of radius 2 dx.
// 3. Re-distance. Every point takes, repeatedly, the nearest disk among its own record and its
//    3^D neighbours' until no record changes (Jacobi sweeps between two buffers: race-free, and
//    the same on every policy). Removed points take the distance to that disk with their new
//    side; kept points keep phi bit for bit unless the nearest disk is farther than |phi| by
//    more than dx / 8: then phi measured the removed feature and becomes the distance to the
//    disk (disks overhang edges by up to 2 dx, so where a removed feature was near an edge the
//    new distance can be short of the true one: 0.6 dx at most on the fin test). Points whose
//    foot lies within about 1.5 spacings of a removed point do not sample the surface.
//    Only packages within three package neighbourhoods (12 spacings, wider than the band) of a
//    removed point may change; the sweeps run three packages farther. Memory while it runs (only when something was removed): four
//    vectors per data point.
//
// Features of half-thickness below 0.45 dx are always removed, those thicker than 2 dx never; in
// between it depends on where the lattice falls. Without a removed point the layer is unchanged.

#include <cmath>
#include <cstdint>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/grid/neighbour_index_shift.hpp"
#include "unisph/grid/package_for.hpp"
#include "unisph/grid/package_grid.hpp"
#include "unisph/memory/discrete_variable.hpp"
#include "unisph/memory/view.hpp"

namespace unisph {

namespace small_feature_kernels {

template <int D>
UNISPH_HOST_DEVICE inline Vec<int, D> local_coordinates(int local_point) {
  Vec<int, D> local;
  for (int k = 0; k < D; ++k) {
    local[k] = local_point % package_size;
    local_point /= package_size;
  }
  return local;
}
// The relative index of neighbour s (0 .. 3^D - 1) of the point at `local`.
template <int D>
UNISPH_HOST_DEVICE inline Vec<int, D> around(const Vec<int, D>& local, int s) {
  Vec<int, D> other = local;
  for (int k = 0; k < D; ++k) {
    other[k] += s % 3 - 1;
    s /= 3;
  }
  return other;
}
UNISPH_HOST_DEVICE inline Index storage(const DataPointAddress& a, int points) {
  return Index(a.package) * points + a.local_point;
}

struct ZeroBytes {
  View<std::int8_t> value;
  UNISPH_HOST_DEVICE void operator()(Index i) const { value[i] = 0; }
};

// fate: 0 kept, +1 removed to the outside, -1 removed to the inside.
template <int D>
struct MarkUnresolved {
  View<const Real> phi;
  View<const PackageNeighbourhood<D>> neighbourhood;
  View<std::int8_t> fate;
  Real resolved;  // 0.45 dx
  UNISPH_HOST_DEVICE void operator()(std::uint32_t package, int local_point) const {
    constexpr int points = package_points<D>;
    const Index i = Index(package) * points + local_point;
    const Real centre = phi[i];
    std::int8_t result = 0;
    if (centre < resolved && centre > -resolved) {
      const Vec<int, D> local = local_coordinates<D>(local_point);
      bool outside = false, inside = false;
      for (int s = 0; s < neighbourhood_size<D>; ++s) {
        const Real value = phi[storage(neighbour_index_shift<D>(around<D>(local, s), neighbourhood[package]), points)];
        outside = outside || value >= resolved;
        inside = inside || value <= -resolved;
      }
      if (!(outside && inside)) result = inside ? std::int8_t(-1) : std::int8_t(1);
    }
    fate[i] = result;
  }
};

template <class T>
struct CopyValues {
  View<const T> from;
  View<T> to;
  UNISPH_HOST_DEVICE void operator()(Index i) const { to[i] = from[i]; }
};

// Packages holding a removed point (the start of the region that cleaning may change).
template <int D>
struct FlagRemovedPackages {
  View<const std::int8_t> fate;
  View<std::uint8_t> region;
  UNISPH_HOST_DEVICE void operator()(std::uint32_t package) const {
    bool any = false;
    for (int l = 0; l < package_points<D>; ++l) any = any || fate[Index(package) * package_points<D> + l] != 0;
    region[package] = any ? 1 : 0;
  }
};
// One dilation of the region by the package neighbourhood (reads one array, writes another).
template <int D>
struct GrowRegion {
  View<const PackageNeighbourhood<D>> neighbourhood;
  View<const std::uint8_t> region;
  View<std::uint8_t> result;
  UNISPH_HOST_DEVICE void operator()(std::uint32_t package) const {
    bool any = false;
    for (int s = 0; s < neighbourhood_size<D>; ++s) {
      const std::uint32_t other = neighbourhood[package].package[s];
      any = any || (other >= far_field_packages && region[other] != 0);
    }
    result[package] = any ? 1 : 0;
  }
};
struct ZeroFlags {
  View<std::uint8_t> value;
  UNISPH_HOST_DEVICE void operator()(Index i) const { value[i] = 0; }
};

struct CountNonZero {
  View<const std::int8_t> value;
  Index offset;
  UNISPH_HOST_DEVICE Index operator()(Index i) const { return value[offset + i] != 0 ? 1 : 0; }
};

// state: the side of every data point after cleaning (+1 outside, -1 inside). Records: the foot
// and normal of kept points with |phi| < near, the others unassigned.
template <int D>
struct StartRecords {
  PackageGrid<D> grid;
  View<const std::uint32_t> cell_package;
  View<const std::uint64_t> package_cell;
  View<const PackageNeighbourhood<D>> neighbourhood;
  View<const Real> phi;
  View<const Vec<Real, D>> normal;
  View<const std::int8_t> fate;
  View<std::int8_t> state;
  View<Vec<Real, D>> record_foot;
  View<Vec<Real, D>> record_normal;
  Real near, unassigned;
  UNISPH_HOST_DEVICE std::int8_t fate_at(const Vec<int, D>& point) const {
    Vec<int, D> cell, local;
    for (int k = 0; k < D; ++k) {
      if (point[k] < 0) return 0;
      cell[k] = point[k] / package_size;
      local[k] = point[k] - cell[k] * package_size;
    }
    if (!grid.contains(cell)) return 0;
    const std::uint32_t package = cell_package[grid.linear(cell)];
    if (package < far_field_packages) return 0;
    return fate[Index(package) * package_points<D> + local_point_index<D>(local)];
  }
  UNISPH_HOST_DEVICE void operator()(std::uint32_t package, int local_point) const {
    const Index i = Index(package) * package_points<D> + local_point;
    const Real value = phi[i];
    const Vec<Real, D> n = normal[i];
    const Vec<Real, D> x = grid.data_position(grid.coordinates(package_cell[package]), local_point);
    const Vec<Real, D> foot = x - value * n;
    const std::int8_t removed = fate[i];
    // A kept point whose foot lies within about 1.5 spacings of a removed point measured the
    // removed feature: it does not sample the kept surface.
    bool by_removed = false;
    if (removed == 0) {
      Vec<int, D> nearest;
      for (int k = 0; k < D; ++k) nearest[k] = int(std::floor((foot[k] - grid.origin[k]) / grid.data_spacing));
      for (int s = 0; s < neighbourhood_size<D> && !by_removed; ++s) by_removed = fate_at(around<D>(nearest, s)) != 0;
    }
    const std::int8_t side = removed != 0 ? removed : (value >= Real(0) ? std::int8_t(1) : std::int8_t(-1));
    state[i] = side;
    // Kept points next to the kept surface sample it, where phi is linear along every axis
    // (forward and backward differences within 0.1 dx): there the normal and the foot are
    // accurate; next to edges and ridges of the distance they are not.
    bool sample = removed == 0 && !by_removed && value < near && value > -near;
    const Vec<int, D> local = local_coordinates<D>(local_point);
    for (int k = 0; k < D && sample; ++k) {
      Vec<int, D> plus = local, minus = local;
      plus[k] += 1;
      minus[k] -= 1;
      const Real forward = phi[storage(neighbour_index_shift<D>(plus, neighbourhood[package]), package_points<D>)] - value;
      const Real backward = value - phi[storage(neighbour_index_shift<D>(minus, neighbourhood[package]), package_points<D>)];
      const Real jump = forward - backward;
      sample = jump < Real(0.1) * grid.data_spacing && jump > Real(-0.1) * grid.data_spacing;
    }
    record_foot[i] = sample ? foot : Vec<Real, D>::constant(unassigned);
    record_normal[i] = n;
  }

};

// Distance from x to the disk of radius r around foot, normal n (|n| = 1).
template <int D>
UNISPH_HOST_DEVICE inline Real distance_to_disk(const Vec<Real, D>& x, const Vec<Real, D>& foot, const Vec<Real, D>& n,
                                                Real radius) {
  const Vec<Real, D> v = x - foot;
  const Real along = dot(v, n);
  const Real t = norm(v - along * n);
  const Real beyond = t > radius ? t - radius : Real(0);
  return std::sqrt(along * along + beyond * beyond);
}

// One Jacobi sweep: each point to re-distance takes the nearest disk among its own record and
// its neighbours' (the disks stay where the surface was sampled, so a tangent plane does not
// travel beyond its disk); reads one pair of record buffers, writes the other; returns 1 where
// a record changed.
template <int D>
struct Redistance {
  PackageGrid<D> grid;
  View<const std::uint64_t> package_cell;
  View<const PackageNeighbourhood<D>> neighbourhood;
  View<const std::int8_t> state;
  View<const std::uint8_t> region;
  View<const Vec<Real, D>> foot_in, normal_in;
  View<Vec<Real, D>> foot_out, normal_out;
  Real disk_radius, unassigned;
  Index offset;  // past the far-field packages
  UNISPH_HOST_DEVICE Index operator()(Index j) const {
    constexpr int points = package_points<D>;
    const Index i = offset + j;
    const std::uint32_t package = std::uint32_t(i / points);
    if (region[package] == 0) return 0;
    const int local_point = int(i % points);
    const Vec<Real, D> x = grid.data_position(grid.coordinates(package_cell[package]), local_point);
    const Vec<int, D> local = local_coordinates<D>(local_point);
    // The own record wins ties, so a distance only ever decreases and the sweeps end.
    Vec<Real, D> best_foot = foot_in[i], best_normal = normal_in[i];
    Real best = best_foot[0] < unassigned ? distance_to_disk<D>(x, best_foot, best_normal, disk_radius) : unassigned;
    for (int s = 0; s < neighbourhood_size<D>; ++s) {
      const DataPointAddress a = neighbour_index_shift<D>(around<D>(local, s), neighbourhood[package]);
      if (a.package < far_field_packages) continue;
      const Index k = storage(a, points);
      const Vec<Real, D> foot = foot_in[k], n = normal_in[k];
      if (!(foot[0] < unassigned) || !(dot(n, n) > Real(0))) continue;
      const Real distance = distance_to_disk<D>(x, foot, n, disk_radius);
      if (distance < best) {
        best = distance;
        best_foot = foot;
        best_normal = n;
      }
    }
    foot_out[i] = best_foot;
    normal_out[i] = best_normal;
    const Vec<Real, D> foot_before = foot_in[i], normal_before = normal_in[i];
    bool same = true;
    for (int d = 0; d < D; ++d) same = same && foot_before[d] == best_foot[d] && normal_before[d] == best_normal[d];
    return same ? 0 : 1;
  }
};

// Back into phi. Removed points: the distance to the nearest disk with their new side. Kept
// points: the same where the kept surface is as near as phi says (within `slack`, the error of
// the disks); where it is farther, phi measured the removed feature: the distance to the disk.
// Where no record arrived, the old distance with the side.
template <int D>
struct WriteBack {
  PackageGrid<D> grid;
  View<const std::uint64_t> package_cell;
  View<const std::int8_t> state, fate;
  View<const std::uint8_t> region;
  View<const Vec<Real, D>> foot, normal;
  View<Real> phi;
  Real disk_radius, unassigned, slack;
  UNISPH_HOST_DEVICE void operator()(std::uint32_t package, int local_point) const {
    if (region[package] == 0) return;
    const Index i = Index(package) * package_points<D> + local_point;
    const Real side = Real(state[i]);
    const Real old = phi[i] >= Real(0) ? phi[i] : -phi[i];
    if (!(foot[i][0] < unassigned)) {
      phi[i] = side * old;
      return;
    }
    const Vec<Real, D> x = grid.data_position(grid.coordinates(package_cell[package]), local_point);
    const Real distance = distance_to_disk<D>(x, foot[i], normal[i], disk_radius);
    if (fate[i] != 0 || distance > old + slack) phi[i] = side * distance;
  }
};

}  // namespace small_feature_kernels

// Cleans phi of one layer (normals as computed from phi before, read to find feet); returns the
// number of removed data points. The caller recomputes the normals when it is not zero.
template <ExecutionPolicy P, class Mesh>
Index clean_small_features(P policy, Mesh& mesh, DiscreteVariable<Real>& phi_variable,
                           DiscreteVariable<Vec<Real, Mesh::dimension>>& normal_variable) {
  constexpr int D = Mesh::dimension;
  namespace k = small_feature_kernels;
  const PackageGrid<D> grid = mesh.grid();
  const Index total = mesh.packages() * package_points<D>;
  const Index offset = Index(far_field_packages) * package_points<D>;
  const Index data_points = total - offset;
  const Real dx = grid.data_spacing;
  DiscreteVariable<std::int8_t> fate("SmallFeatureFate", total);
  particle_for(policy, offset, k::ZeroBytes{fate.write(policy)});
  data_point_for(policy, mesh,
                 k::MarkUnresolved<D>{phi_variable.read(policy), mesh.neighbourhood.read(policy), fate.write(policy),
                                      dx * Real(0.45)});
  const Index removed = particle_reduce(policy, data_points, Sum<Index>{}, k::CountNonZero{fate.read(policy), offset});
  if (removed == 0) return 0;

  // The region cleaning may change: packages within three package neighbourhoods (12 spacings,
  // more than the band is wide) of a removed point.
  DiscreteVariable<std::uint8_t> region("SmallFeatureRegion", mesh.packages()), grown("SmallFeatureGrown", mesh.packages());
  particle_for(policy, Index(far_field_packages), k::ZeroFlags{region.write(policy)});
  particle_for(policy, Index(far_field_packages), k::ZeroFlags{grown.write(policy)});
  package_for(policy, mesh, k::FlagRemovedPackages<D>{fate.read(policy), region.read_write(policy)});
  package_for(policy, mesh, k::GrowRegion<D>{mesh.neighbourhood.read(policy), region.read(policy), grown.read_write(policy)});
  package_for(policy, mesh, k::GrowRegion<D>{mesh.neighbourhood.read(policy), grown.read(policy), region.read_write(policy)});
  package_for(policy, mesh, k::GrowRegion<D>{mesh.neighbourhood.read(policy), region.read(policy), grown.read_write(policy)});
  // The sweeps run three packages farther, so that the records arriving at the region's border
  // come from the samples nearest to it, which may lie outside.
  DiscreteVariable<std::uint8_t> swept("SmallFeatureSwept", mesh.packages());
  particle_for(policy, Index(far_field_packages), k::ZeroFlags{swept.write(policy)});
  package_for(policy, mesh, k::GrowRegion<D>{mesh.neighbourhood.read(policy), grown.read(policy), swept.read_write(policy)});
  package_for(policy, mesh, k::GrowRegion<D>{mesh.neighbourhood.read(policy), swept.read(policy), region.read_write(policy)});
  package_for(policy, mesh, k::GrowRegion<D>{mesh.neighbourhood.read(policy), region.read(policy), swept.read_write(policy)});

  // A value no distance in the layer reaches (the far field holds two coarse cell sizes).
  const Real unassigned = Real(1e30);
  DiscreteVariable<std::int8_t> state("SmallFeatureState", total);
  DiscreteVariable<Vec<Real, D>> foot_a("SmallFeatureFootA", total), foot_b("SmallFeatureFootB", total);
  DiscreteVariable<Vec<Real, D>> normal_a("SmallFeatureNormalA", total), normal_b("SmallFeatureNormalB", total);
  {
    // Far-field slots: no record (their normal is zero), never re-distanced.
    View<std::int8_t> s = state.write(policy);
    View<Vec<Real, D>> f = foot_a.write(policy), n = normal_a.write(policy);
    particle_for(policy, offset, k::ZeroBytes{s});
    particle_for(policy, offset, k::CopyValues<Vec<Real, D>>{normal_variable.read(policy), n});
    particle_for(policy, offset, k::CopyValues<Vec<Real, D>>{n, f});
    data_point_for(policy, mesh,
                   k::StartRecords<D>{grid, mesh.cell_package.read(policy), mesh.package_cell.read(policy),
                                      mesh.neighbourhood.read(policy), phi_variable.read(policy),
                                      normal_variable.read(policy), fate.read(policy), s, f, n, dx,
                                      unassigned});
  }
  particle_for(policy, total, k::CopyValues<Vec<Real, D>>{foot_a.read(policy), foot_b.write(policy)});
  particle_for(policy, total, k::CopyValues<Vec<Real, D>>{normal_a.read(policy), normal_b.write(policy)});
  // Disks of two spacings: they bridge the strip of the kept surface next to a removed feature
  // that has no samples (there phi had a ridge between the feature and the surface); smaller
  // ones leave gaps at edges and corners, where the nearest disk is then too far (measured on
  // the fin test: radius dx left errors of 1 dx, 2 dx none).
  const Real disk_radius = Real(2) * dx;
  bool in_a = true;
  for (int sweep = 0; sweep < 1000; ++sweep) {
    DiscreteVariable<Vec<Real, D>>& foot_in = in_a ? foot_a : foot_b;
    DiscreteVariable<Vec<Real, D>>& foot_out = in_a ? foot_b : foot_a;
    DiscreteVariable<Vec<Real, D>>& normal_in = in_a ? normal_a : normal_b;
    DiscreteVariable<Vec<Real, D>>& normal_out = in_a ? normal_b : normal_a;
    const Index changed = particle_reduce(
        policy, data_points, Sum<Index>{},
        k::Redistance<D>{grid, mesh.package_cell.read(policy), mesh.neighbourhood.read(policy), state.read(policy),
                         swept.read(policy), foot_in.read(policy), normal_in.read(policy), foot_out.read_write(policy),
                         normal_out.read_write(policy), disk_radius, unassigned, offset});
    in_a = !in_a;
    if (changed == 0) break;
  }
  data_point_for(policy, mesh,
                 k::WriteBack<D>{grid, mesh.package_cell.read(policy), state.read(policy), fate.read(policy), grown.read(policy),
                                 (in_a ? foot_a : foot_b).read(policy), (in_a ? normal_a : normal_b).read(policy),
                                 phi_variable.read_write(policy), disk_radius, unassigned, dx * Real(0.125)});
  fence(policy);
  return removed;
}

}  // namespace unisph
