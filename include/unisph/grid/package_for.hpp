#pragma once
// Loops of a package mesh, on every policy:
//   package_for(policy, mesh, kernel)     kernel(package) for every package with data (index >= 2)
//   data_point_for(policy, mesh, kernel)  kernel(package, local_point) for every data point of them
//   mesh_for(policy, grid, kernel)        kernel(cell) for every cell of the background mesh
// The kernels follow particle_for's rules (trivially copyable, UNISPH_HOST_DEVICE call operator).
//
// package_for and data_point_for walk the hierarchy packages -> data points with iter::View
// (iter/package_traits.hpp: PackagesOfMesh, child PackageDataPoints, whose slots name a package
// and a data point), one walk per data package (docs/views.md, "Package loops"):
//
//   data_point_for  seq, par     one item of particle_for per package: its view, one worker
//                                (collectivity::None), visits the package's 4^D points in order
//                   par_device   a team of 4^D threads per package (collective_for<4^D>: blocks of
//                                256 threads = 4 teams of 64 in 3D, 16 teams of 16 in 2D) sharing the
//                                package's points view, one point per thread: the thread layout of a
//                                flat loop over the data points (thread i: package i / 4^D, point i % 4^D)
//   package_for     every policy  one item of particle_for per package, a view of that package
//
// Both are one walk (PackageWalk) whose team is the view's Collectivity.

#include <cstdint>
#include <type_traits>

#include "unisph/exec/algorithms.hpp"
#include "unisph/grid/cell_tag.hpp"
#include "unisph/grid/package_grid.hpp"
#include "unisph/iter/collective_for.hpp"
#include "unisph/grid/package_traits.hpp"
#include "unisph/iter/view.hpp"

namespace unisph {

namespace detail {

// The walk of the q-th data package of `packages` (package first_data_package + q):
// with Points, the view of its data points shared by `team` (kernel(package, local_point) for
// each); without, the package itself (kernel(package)).
template <int D, bool Points, class F>
struct PackageWalk {
  iter::PackagesOfMesh<D> packages;
  F kernel;

  template <class Team>
  UNISPH_HOST_DEVICE void operator()(const Team& team, Index q) const {
    // A view of the one package q: every element of a run of one (compile-time offset 0 and jump
    // 1, one worker), so the view hands it out without a test and its child is a whole package.
    using One = iter::CompileTimeTuple<>;
    if constexpr (Points) {
      using PointsView = iter::View<iter::PackageDataPoints<D>, iter::direction::Forward, Team, One>;
      const iter::View<iter::PackagesOfMesh<D>, iter::direction::Forward, iter::collectivity::None, One, PointsView> view(
          packages.part(q, 1), One{}, PointsView(nullptr, One{}, iter::NoChild{}, team));
      view.for_each([&](const iter::ValueSlot<DataPointAddress>& slot) {
        if (slot) kernel(slot->package, slot->local_point);
      });
    } else {
      const iter::View<iter::PackagesOfMesh<D>, iter::direction::Forward, iter::collectivity::None, One> view(
          packages.part(q, 1));
      view.for_each([&](const iter::ValueSlot<std::uint32_t>& slot) {
        if (slot) kernel(*slot);
      });
    }
  }
};

// A walk by one worker per item of particle_for (the host's loops; package_for everywhere).
template <class Walk>
struct WalkAlone {
  Walk walk;
  UNISPH_HOST_DEVICE void operator()(Index q) const { walk(iter::collectivity::None{}, q); }
};

template <class F>
constexpr void check_package_kernel() {
  static_assert(std::is_trivially_copyable_v<F>,
                "a package_for / data_point_for kernel is copied byte for byte into every launch (to the GPU as well), "
                "so it must be trivially copyable: hold Views and plain values, not std::vector, references or virtual "
                "functions.");
}

}  // namespace detail

template <ExecutionPolicy P, class Mesh, class F>
void package_for(P policy, const Mesh& mesh, const F& kernel) {
  detail::check_package_kernel<F>();
  static_assert(std::is_invocable_v<const F&, std::uint32_t>,
                "package_for calls its kernel as kernel(package) with a std::uint32_t package index.");
  constexpr int D = Mesh::dimension;
  using Walk = detail::PackageWalk<D, false, F>;
  particle_for(policy, mesh.data_packages(), detail::WalkAlone<Walk>{Walk{iter::PackagesOfMesh<D>::of(mesh), kernel}});
}

template <ExecutionPolicy P, class Mesh, class F>
void data_point_for(P policy, const Mesh& mesh, const F& kernel) {
  detail::check_package_kernel<F>();
  static_assert(std::is_invocable_v<const F&, std::uint32_t, int>,
                "data_point_for calls its kernel as kernel(package, local_point) with a std::uint32_t package index and "
                "an int local point (0 .. 4^D - 1).");
  constexpr int D = Mesh::dimension;
  using Walk = detail::PackageWalk<D, true, F>;
  const Walk walk{iter::PackagesOfMesh<D>::of(mesh), kernel};
  if constexpr (P::space == MemorySpace::device)
    iter::collective_for<Index(package_points<D>)>(policy, mesh.data_packages(), walk);
  else
    particle_for(policy, mesh.data_packages(), detail::WalkAlone<Walk>{walk});
}

template <ExecutionPolicy P, int D, class F>
void mesh_for(P policy, const PackageGrid<D>& grid, const F& kernel) {
  particle_for(policy, grid.cell_count(), kernel);
}

}  // namespace unisph
