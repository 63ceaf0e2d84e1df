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
// 2. Sample the kept surface. Kept points whose closest point is not on the removed feature
//    record a point of the kept surface, by the axis differences of phi and of phi^2 (phi^2 is
//    a quadratic polynomial where phi is the distance to one plane, straight line or point, so
//    its central differences give the closest point exactly and its second differences the
//    trace of the projector onto the feature's normal space: 1 on a face, 2 on an edge, 3 at a
//    corner):
//    - face samples (trace near 1, phi linear along every axis, x - phi n and x - phi^2 / 2's
//      gradient agreeing): the foot x - phi n and the normal n, a tangent disk of radius 2 dx;
//    - edge and corner samples (trace near 2 or 3, |grad(phi^2) / 2| = |phi|): the closest point
//      alone, with no disk, so that nothing reaches beyond an edge of the kept shape.
//    Next to ridges of the distance (two features across the stencil) neither holds. Feet within
//    about 1.5 spacings of a removed point (on the removed feature, or on the kept surface that
//    it hid) are not recorded.
// 3. Re-distance. Every point takes, repeatedly, the record whose foot is nearest among its own
//    and its 3^D neighbours' until no record changes (a closest-point transform by Jacobi sweeps
//    between two buffers: race-free, and the same on every policy). The nearest foot lies next to
//    the point's closest point of the kept surface, so the sample evaluated there is the one
//    tangent there: a face's disk spans the strip of the kept surface next to the removed feature
//    that has no samples, and an edge or corner answers with its own points, not with a face's
//    disk overhanging it (the overhang of disks chosen by the distance to the disk itself was up
//    to 0.61 dx on the fin test). Removed points take the distance to that sample with their new
//    side; kept points keep phi bit for bit unless they may have measured the removed feature
//    (a removed point may lie within |phi| + 2 dx, judged by the package distance) and the sample
//    is farther than |phi| by more than dx / 32: then phi becomes the distance to the sample.
//    Only packages within three package neighbourhoods (12 spacings, wider than the band) of a
//    removed point may change; the sweeps run three packages farther. Memory while it runs (only
//    when something was removed): four vectors per data point.
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
        const Real value = phi[storage(neighbour_index_shift<D>(neighbour_in_block<D>(local, s), neighbourhood[package]), points)];
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
// The region holds levels: 1 for a package with a removed point, L for one whose nearest such
// package is L - 1 packages away (Chebyshev), 0 outside.
template <int D>
struct GrowRegion {
  View<const PackageNeighbourhood<D>> neighbourhood;
  View<const std::uint8_t> region;
  View<std::uint8_t> result;
  UNISPH_HOST_DEVICE void operator()(std::uint32_t package) const {
    std::uint8_t level = region[package];
    for (int s = 0; s < neighbourhood_size<D>; ++s) {
      const std::uint32_t other = neighbourhood[package].package[s];
      if (other < far_field_packages || region[other] == 0) continue;
      const std::uint8_t next = std::uint8_t(region[other] + 1);
      level = level == 0 || next < level ? next : level;
    }
    result[package] = level;
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
// and normal (zero for edge and corner samples) of kept points that sample the kept surface,
// the others unassigned.
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
  Real unassigned;
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
  // A foot within about 1.5 spacings of a removed point lies on the removed feature (or where
  // the kept surface is hidden by it): it does not sample the kept surface.
  UNISPH_HOST_DEVICE bool by_removed(const Vec<Real, D>& foot) const {
    Vec<int, D> nearest;
    for (int k = 0; k < D; ++k) nearest[k] = int(std::floor((foot[k] - grid.origin[k]) / grid.data_spacing));
    bool found = false;
    for (int s = 0; s < neighbourhood_size<D> && !found; ++s) found = fate_at(neighbour_in_block<D>(nearest, s)) != 0;
    return found;
  }
  UNISPH_HOST_DEVICE void operator()(std::uint32_t package, int local_point) const {
    const Index i = Index(package) * package_points<D> + local_point;
    const Real value = phi[i];
    const Vec<Real, D> n = normal[i];
    const Vec<Real, D> x = grid.data_position(grid.coordinates(package_cell[package]), local_point);
    const Vec<Real, D> foot = x - value * n;
    const std::int8_t removed = fate[i];
    const std::int8_t side = removed != 0 ? removed : (value >= Real(0) ? std::int8_t(1) : std::int8_t(-1));
    state[i] = side;
    // Kept points sample the kept surface where the axis differences show one feature of the
    // surface across the stencil. Per axis k: the jump of phi (forward minus backward
    // difference), and from q = phi^2 the half central difference g_k (= phi dphi/dx_k) and the
    // half second difference s_k (the diagonal of the Hessian of phi^2 / 2). phi^2 is a quadratic
    // polynomial wherever phi is the distance to one plane, one straight line or one point, so
    // there these differences are exact: x - g is the closest point, |g| = |phi|, and the Hessian
    // is the projector onto the normal space of the feature, whose trace (the sum of s_k) is 1 on
    // a face, 2 at an edge, 3 at a corner (D - 1 .. D in D dimensions); on a face of curvature
    // kappa it is 1 + (D - 1) phi kappa / (1 + phi kappa).
    //  - face samples (trace within 1/4 of 1, phi linear along every axis: jumps within 0.1 dx,
    //    x - phi n and x - g within 0.05 dx per axis): the foot x - phi n and the normal n, a
    //    tangent disk (a stencil straddling a face and an edge's region gives a trace between 1
    //    and 2 and a blended normal, whose disk would cut corners);
    //  - edge and corner samples (trace within 0.1 of 2 or 3, every s_k in [-0.05, 1.05],
    //    ||g| - |phi|| < 0.02 dx): the foot x - g alone, a point (normal zero). A disk there
    //    would reach beyond the edge.
    // Next to ridges of the distance (two features across the stencil) neither holds.
    const Vec<int, D> local = local_coordinates<D>(local_point);
    const Real h = grid.data_spacing;
    bool linear = true, second_ok = true;
    Real trace = Real(0);
    Vec<Real, D> g{};
    for (int k = 0; k < D; ++k) {
      Vec<int, D> plus = local, minus = local;
      plus[k] += 1;
      minus[k] -= 1;
      const Real up = phi[storage(neighbour_index_shift<D>(plus, neighbourhood[package]), package_points<D>)];
      const Real down = phi[storage(neighbour_index_shift<D>(minus, neighbourhood[package]), package_points<D>)];
      const Real jump = (up - value) - (value - down);
      linear = linear && jump < Real(0.1) * h && jump > Real(-0.1) * h;
      const Real q_up = up * up, q_down = down * down, q = value * value;
      g[k] = (q_up - q_down) / (Real(4) * h);
      const Real second = (q_up + q_down - Real(2) * q) / (Real(2) * h * h);
      second_ok = second_ok && second > Real(-0.05) && second < Real(1.05);
      trace += second;
    }
    bool consistent = true;  // the two closest points, x - phi n and x - g, agree
    for (int k = 0; k < D; ++k) {
      const Real apart = g[k] - value * n[k];
      consistent = consistent && apart < Real(0.05) * h && apart > Real(-0.05) * h;
    }
    const bool face = removed == 0 && trace > Real(0.75) && trace < Real(1.25) && linear && consistent && !by_removed(foot);
    const Real magnitude = value >= Real(0) ? value : -value;
    const Real g_error = norm(g) - magnitude;
    bool point = false;
    for (int m = D - 1; m <= D && !face && removed == 0 && second_ok; ++m) {
      const Real off = trace - Real(m);
      point = point || (m >= 2 && off < Real(0.1) && off > Real(-0.1));
    }
    point = point && g_error < Real(0.02) * h && g_error > Real(-0.02) * h && !by_removed(x - g);
    record_foot[i] = face ? foot : (point ? Vec<Real, D>(x - g) : Vec<Real, D>::constant(unassigned));
    record_normal[i] = face ? n : Vec<Real, D>{};
  }

};

// Distance from x to a sample of the kept surface: the disk of radius r around foot with normal
// n (|n| = 1) for a face sample, the foot itself for an edge or corner sample (n = 0).
template <int D>
UNISPH_HOST_DEVICE inline Real distance_to_disk(const Vec<Real, D>& x, const Vec<Real, D>& foot, const Vec<Real, D>& n,
                                                Real radius) {
  const Vec<Real, D> v = x - foot;
  if (!(squared_norm(n) > Real(0))) return std::sqrt(squared_norm(v));
  const Real along = dot(v, n);
  const Real t = norm(v - along * n);
  const Real beyond = t > radius ? t - radius : Real(0);
  return std::sqrt(along * along + beyond * beyond);
}

// One Jacobi sweep: each point to re-distance takes the record with the nearest foot among its
// own and its neighbours' (the samples stay where the surface was sampled); reads one pair of
// record buffers, writes the other; returns 1 where a record changed.
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
    // The records are ranked by the distance to their foot (a point of the kept surface), not
    // by the distance to their disk: the nearest foot lies next to the point's closest point of
    // the kept surface, so the disk evaluated afterwards (WriteBack) is the one tangent there,
    // and a face's disk near an edge does not win over the edge's own samples beyond it. The own
    // record wins ties, so the distance only ever decreases and the sweeps end.
    Vec<Real, D> best_foot = foot_in[i], best_normal = normal_in[i];
    Real best = best_foot[0] < unassigned ? squared_norm(x - best_foot) : unassigned;
    for (int s = 0; s < neighbourhood_size<D>; ++s) {
      const DataPointAddress a = neighbour_index_shift<D>(neighbour_in_block<D>(local, s), neighbourhood[package]);
      if (a.package < far_field_packages) continue;
      const Index k = storage(a, points);
      const Vec<Real, D> foot = foot_in[k];
      if (!(foot[0] < unassigned)) continue;
      const Real distance = squared_norm(x - foot);
      if (distance < best) {
        best = distance;
        best_foot = foot;
        best_normal = normal_in[k];
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

// Back into phi. Removed points: the distance to the nearest sample with their new side. Kept
// points: phi bit for bit, unless the point may have measured the removed feature and the
// sample is farther than phi says by more than `slack`: then phi measured the removed feature,
// and becomes the distance to the sample. A kept point may have measured the removed feature
// when a removed point can lie within |phi| + 2 dx of it; its package's level bounds the
// distance to the nearest removed point from below by ((level - 2) * package_size + 1) dx.
// (Every point of a removed feature's surface lies within about one spacing of a removed point;
// the bound keeps the samples' own error, largest next to the kept shape's corners, away from
// points far from the removed feature.) Where no record arrived, the old distance with the side.
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
    const std::uint8_t level = region[package];
    if (level == 0) return;
    const Index i = Index(package) * package_points<D> + local_point;
    const Real side = Real(state[i]);
    const Real old = phi[i] >= Real(0) ? phi[i] : -phi[i];
    if (!(foot[i][0] < unassigned)) {
      phi[i] = side * old;
      return;
    }
    const Real dx = grid.data_spacing;
    const Real removed_at_least = level >= 2 ? Real((int(level) - 2) * package_size + 1) * dx : Real(0);
    const bool may_have_measured = old + Real(2) * dx >= removed_at_least;
    const Vec<Real, D> x = grid.data_position(grid.coordinates(package_cell[package]), local_point);
    const Real distance = distance_to_disk<D>(x, foot[i], normal[i], disk_radius);
    if (fate[i] != 0 || (may_have_measured && distance > old + slack)) phi[i] = side * distance;
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
                                      normal_variable.read(policy), fate.read(policy), s, f, n, unassigned});
  }
  particle_for(policy, total, k::CopyValues<Vec<Real, D>>{foot_a.read(policy), foot_b.write(policy)});
  particle_for(policy, total, k::CopyValues<Vec<Real, D>>{normal_a.read(policy), normal_b.write(policy)});
  // Disks of two spacings: they bridge the strip of the kept surface next to a removed feature
  // that has no samples (there phi had a ridge between the feature and the surface). They cannot
  // overhang an edge by much: a disk is only evaluated where its foot is the nearest, and edges
  // and corners carry their own samples.
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
                                 phi_variable.read_write(policy), disk_radius, unassigned, dx * Real(0.03125)});
  fence(policy);
  return removed;
}

}  // namespace unisph
