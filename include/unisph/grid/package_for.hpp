#pragma once
// Loops of a package mesh, on every policy:
//   package_for(policy, mesh, kernel)     kernel(package) for every package with data (index >= 2)
//   data_point_for(policy, mesh, kernel)  kernel(package, local_point) for every data point of them
//   mesh_for(policy, grid, kernel)        kernel(cell) for every cell of the background mesh
// The kernels follow particle_for's rules (trivially copyable, UNISPH_HOST_DEVICE call operator).

#include <type_traits>

#include "unisph/exec/algorithms.hpp"
#include "unisph/grid/cell_tag.hpp"
#include "unisph/grid/package_grid.hpp"

namespace unisph {

namespace detail {
template <class F>
struct ShiftPastFarField {
  F kernel;
  UNISPH_HOST_DEVICE void operator()(Index i) const { kernel(std::uint32_t(i + far_field_packages)); }
};
template <int D, class F>
struct SplitDataPoint {
  F kernel;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    kernel(std::uint32_t(i / package_points<D> + far_field_packages), int(i % package_points<D>));
  }
};
}  // namespace detail

template <ExecutionPolicy P, class Mesh, class F>
void package_for(P policy, const Mesh& mesh, const F& kernel) {
  particle_for(policy, mesh.data_packages(), detail::ShiftPastFarField<F>{kernel});
}

template <ExecutionPolicy P, class Mesh, class F>
void data_point_for(P policy, const Mesh& mesh, const F& kernel) {
  constexpr int D = Mesh::dimension;
  particle_for(policy, mesh.data_packages() * Index(package_points<D>), detail::SplitDataPoint<D, F>{kernel});
}

template <ExecutionPolicy P, int D, class F>
void mesh_for(P policy, const PackageGrid<D>& grid, const F& kernel) {
  particle_for(policy, grid.cell_count(), kernel);
}

}  // namespace unisph
