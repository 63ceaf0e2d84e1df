#pragma once
// One resolution of a multi-resolution level set: a package mesh over the cells whose tags
// say core or inner, the signed distance phi at every data point of its packages and the unit
// normal from phi, the kernel integrals over the outside (kernel_integrals.hpp). The far-field
// packages hold +far_field_distance (outside) and -far_field_distance (inside), two cell sizes,
// a zero normal, kernel weight 1 (outside) or 0 (inside) and a zero kernel gradient.
//
// Built by MultiResolutionLevelSet, stage by stage, each stage a kernel on the chosen policy.

#include <cmath>
#include <cstdint>
#include <limits>

#include "unisph/exec/algorithms.hpp"
#include "unisph/geometry/triangle_batch_nearest.hpp"
#include "unisph/geometry/triangle_batch_winding.hpp"
#include "unisph/grid/package_for.hpp"
#include "unisph/grid/package_mesh.hpp"
#include "unisph/levelset/kernel_integrals.hpp"
#include "unisph/levelset/level_set_layer_view.hpp"
#include "unisph/levelset/regularized_gradient.hpp"
#include "unisph/levelset/shape_search.hpp"
#include "unisph/memory/discrete_variable.hpp"
#include "unisph/core/uncontracted_arithmetic.hpp"

namespace unisph {

namespace level_set_kernels {
template <int D>
struct FarFieldValues {
  View<Real> phi;
  Real distance;
  UNISPH_HOST_DEVICE void operator()(Index i) const { phi[i] = i < Index(package_points<D>) ? distance : -distance; }
};
template <int D>
struct FarFieldNormals {
  View<Vec<Real, D>> normal;
  UNISPH_HOST_DEVICE void operator()(Index i) const { normal[i] = Vec<Real, D>{}; }
};
template <int D>
struct FarFieldKernelIntegrals {
  View<Real> weight;
  View<Vec<Real, D>> gradient;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    weight[i] = i < Index(package_points<D>) ? Real(1) : Real(0);
    gradient[i] = Vec<Real, D>{};
  }
};
// Distance to the nearest feature at every data point. The sign: in a core package from the
// shape at the point; in an inner package from the cell's side (decided at its centre, or by
// the flood fill on the coarsest layer): a cell that is not core lies wholly on one side, since
// its half diagonal (0.87 cell sizes) is shorter than its centre's distance to the surface.
// That saves the per-point sign (the winding number, the dearer half of the work) in inner packages.
template <int D, class Shape>
struct SignedDistanceAtDataPoints {
  Shape shape;
  PackageGrid<D> grid;
  View<const std::uint64_t> package_cell;
  View<const PackageType> package_type;
  View<const CellTag> cell_side;
  View<Real> phi;
  UNISPH_HOST_DEVICE void operator()(std::uint32_t package, int local_point) const {
    const Index cell = package_cell[package];
    const Vec<Real, D> x = grid.data_position(grid.coordinates(cell), local_point);
    const auto nearest = shape.nearest(x);
    const Real distance = std::sqrt(nearest.squared_distance);
    const bool outside = package_type[package] == PackageType::core ? shape.sign(x, nearest) > 0
                                                                     : cell_side[cell] != CellTag::inside;
    phi[Index(package) * package_points<D> + local_point] = outside ? distance : -distance;
  }
};
// The same, one package at a time, for shapes that search a triangle mesh (on the host policies):
// the package's 64 data points share one walk of the BVH and a vectorised float filter of the
// candidate triangles (triangle_batch_nearest.hpp), which gives every point the nearest triangle
// that shape.nearest would; the sign and phi are then computed as above (the winding number's
// sides of the 64 points in one walk too, triangle_batch_winding.hpp).
//
// With a finer layer (children_tag not empty) the batch also holds the centres of the cell's 8
// children on that layer: their tags (decide_cell's, on the finer grid) and their squared
// distances (rounded up to float) go to children_tag / children_distance2 at 8 * package + j,
// child j = 2 * cell + (j & 1, j >> 1 & 1, j >> 2), so the finer layer's tagging reads them
// (TagChildrenFromCoarsePackages) and its packages' batches start from them instead of a
// nearest query at their centres (coarse_children_distance2 of the coarser layer; empty: query).
template <class Shape>
struct SignedDistanceInPackages {
  Shape shape;
  PackageGrid<3> grid;
  View<const std::uint64_t> package_cell;
  View<const PackageType> package_type;
  View<const CellTag> cell_side;
  View<Real> phi;
  PackageGrid<3> coarse_grid{};
  View<const std::uint32_t> coarse_cell_package{};
  View<const float> coarse_children_distance2{};
  PackageGrid<3> fine_grid{};
  View<CellTag> children_tag{};
  View<float> children_distance2{};

  UNISPH_HOST_DEVICE void operator()(std::uint32_t package) const {
    if (children_tag.size() > 0)
      run<package_points<3> + 8>(package);
    else
      run<package_points<3>>(package);
  }

  template <int Points>
  UNISPH_HOST_DEVICE void run(std::uint32_t package) const {
    constexpr int n = package_points<3>;
    const Index cell = package_cell[package];
    const Vec<int, 3> coordinates = grid.coordinates(cell);
    Vec<Real, 3> x[Points];
    for (int i = 0; i < n; ++i) x[i] = grid.data_position(coordinates, i);
    for (int j = 0; j < Points - n; ++j) {
      Vec<int, 3> child;
      for (int k = 0; k < 3; ++k) child[k] = 2 * coordinates[k] + ((j >> k) & 1);
      x[n + j] = fine_grid.cell_centre(child);
    }
    const Vec<Real, 3> centre = grid.cell_centre(coordinates);
    const TriangleMeshSearchView& mesh = triangle_mesh_of(shape);
    Real centre_squared_distance;
    if (coarse_children_distance2.size() > 0) {
      Vec<int, 3> parent;
      int j = 0;
      for (int k = 0; k < 3; ++k) parent[k] = coordinates[k] / 2, j |= (coordinates[k] & 1) << k;
      centre_squared_distance = Real(coarse_children_distance2[Index(coarse_cell_package[coarse_grid.linear(parent)]) * 8 + j]);
    } else {
      centre_squared_distance = mesh.nearest(centre).squared_distance;
    }
    NearestTriangle nearest[Points];
    batch_nearest<Points>(mesh, centre, centre_squared_distance, x, nearest);
    const bool core = package_type[package] == PackageType::core;
    const bool side_outside = cell_side[cell] != CellTag::inside;
    if constexpr (signs_by_winding_number<Shape>) {
      bool inside[n];
      if (core) batch_winding_inside<n>(mesh, centre, x, ~std::uint64_t(0), inside);
      for (int i = 0; i < n; ++i) {
        const Real distance = std::sqrt(nearest[i].squared_distance);
        const bool outside = core ? !inside[i] : side_outside;
        phi[Index(package) * n + i] = outside ? distance : -distance;
      }
    } else {
      for (int i = 0; i < n; ++i) {
        const Real distance = std::sqrt(nearest[i].squared_distance);
        const bool outside = core ? shape.sign(x[i], nearest[i]) > 0 : side_outside;
        phi[Index(package) * n + i] = outside ? distance : -distance;
      }
    }
    if constexpr (Points > n) {
      // decide_cell_from on the finer grid, for the children.
      const Real size = fine_grid.cell_size();
      const Real size2 = uncontracted::mul(size, size);
      bool inside[8] = {};
      if constexpr (signs_by_winding_number<Shape>) {
        std::uint64_t wanted = 0;
        for (int j = 0; j < 8; ++j)
          if (!(nearest[n + j].squared_distance < size2)) wanted |= std::uint64_t(1) << j;
        batch_winding_inside<8>(mesh, centre, x + n, wanted, inside);
      } else {
        for (int j = 0; j < 8; ++j)
          if (!(nearest[n + j].squared_distance < size2)) inside[j] = !(shape.sign(x[n + j], nearest[n + j]) > 0);
      }
      for (int j = 0; j < 8; ++j) {
        const Index slot = Index(package) * 8 + j;
        children_tag[slot] = nearest[n + j].squared_distance < size2 ? CellTag::core
                             : inside[j]                             ? CellTag::inside
                                                                     : CellTag::outside;
        const Real d2 = nearest[n + j].squared_distance;
        float bound = float(d2);
        if (Real(bound) < d2) bound = std::nextafter(bound, std::numeric_limits<float>::infinity());
        children_distance2[slot] = bound;
      }
    }
  }
};
// kernel(package) once per package, launched over the data points (on the first of each). It was
// written when data_point_for gave each host task 2048 data points (32 packages); data_point_for
// now hands the host one package per item, as package_for does, yet this launch stayed faster:
// package_for(policy, mesh, kernel) in its place took the distance stage at N = 1024 on one thread
// from 3.90 to 4.43-4.50 s (session 7, 2-core VM). Why was not found; kept for that.
template <class F>
struct OncePerPackage {
  F kernel;
  UNISPH_HOST_DEVICE void operator()(std::uint32_t package, int local_point) const {
    if (local_point == 0) kernel(package);
  }
};
template <int D>
struct NormalFromPhi {
  View<const Real> phi;
  View<const PackageNeighbourhood<D>> neighbourhood;
  View<Vec<Real, D>> normal;
  Real spacing;
  UNISPH_HOST_DEVICE void operator()(std::uint32_t package, int local_point) const {
    const Vec<Real, D> g = regularized_gradient<D>(phi, neighbourhood[package], package, local_point, spacing);
    const Real length = norm(g);
    normal[Index(package) * package_points<D> + local_point] = length > Real(0) ? g / length : g;
  }
};
}  // namespace level_set_kernels

template <int D>
class LevelSetLayer {
 public:
  static constexpr int dimension = D;

  explicit LevelSetLayer(const PackageGrid<D>& grid)
      : mesh(grid),
        tags("CellTag", grid.cell_count()),
        cell_side("CellSide", grid.cell_count()),
        far_field_distance(Real(2) * grid.cell_size()) {}

  const PackageGrid<D>& grid() const { return mesh.grid(); }
  Index packages() const { return mesh.packages(); }
  Index data_packages() const { return mesh.data_packages(); }

  // Packages from the tags, then phi at every data point (the sign from the surface).
  template <ExecutionPolicy P>
  void allocate_packages(P policy) {
    mesh.allocate(policy, tags);
  }
  // coarser: the layer above (its children_distance2 then serve as the centres' distances);
  // finer: the next layer's grid (children_tag and children_distance2 are then filled). Both are
  // used on the host policies with a triangle mesh only (SignedDistanceInPackages).
  template <ExecutionPolicy P, class Shape>
  void compute_signed_distance(P policy, const Shape& shape, LevelSetLayer* coarser = nullptr,
                               const PackageGrid<D>* finer = nullptr) {
    namespace k = level_set_kernels;
    phi.resize(packages() * package_points<D>);
    View<Real> values = phi.write(policy);
    particle_for(policy, Index(far_field_packages) * package_points<D>, k::FarFieldValues<D>{values, far_field_distance});
    if constexpr (D == 3 && P::space == MemorySpace::host && searches_triangle_mesh<Shape>) {
      k::SignedDistanceInPackages<Shape> kernel{shape, grid(), mesh.package_cell.read(policy),
                                                mesh.package_type.read(policy), cell_side.read(policy), values};
      if (coarser != nullptr && coarser->children_distance2.size() > 0) {
        kernel.coarse_grid = coarser->grid();
        kernel.coarse_cell_package = coarser->mesh.cell_package.read(policy);
        kernel.coarse_children_distance2 = coarser->children_distance2.read(policy);
      }
      if (finer != nullptr) {
        children_tag.resize(packages() * 8);
        children_distance2.resize(packages() * 8);
        kernel.fine_grid = *finer;
        kernel.children_tag = children_tag.write(policy);
        kernel.children_distance2 = children_distance2.write(policy);
      }
      data_point_for(policy, mesh, k::OncePerPackage<k::SignedDistanceInPackages<Shape>>{kernel});
    } else {
      data_point_for(policy, mesh,
                     k::SignedDistanceAtDataPoints<D, Shape>{shape, grid(), mesh.package_cell.read(policy),
                                                             mesh.package_type.read(policy), cell_side.read(policy),
                                                             values});
    }
    fence(policy);
  }
  // The normals' array is allocated here on the first call (its far-field packages zero), not
  // with phi: the distance stage does not pay for it.
  template <ExecutionPolicy P>
  void compute_normals(P policy) {
    View<Vec<Real, D>> values;
    if (normal.size() != packages() * package_points<D>) {
      normal.resize(packages() * package_points<D>);
      values = normal.write(policy);
      particle_for(policy, Index(far_field_packages) * package_points<D>, level_set_kernels::FarFieldNormals<D>{values});
    } else {
      values = normal.read_write(policy);
    }
    data_point_for(policy, mesh,
                   level_set_kernels::NormalFromPhi<D>{phi.read(policy), mesh.neighbourhood.read(policy), values,
                                                       grid().data_spacing});
    fence(policy);
  }

  // Kernel integrals (kernel_integrals.hpp) at every data point, from phi and the normal.
  template <ExecutionPolicy P>
  void compute_kernel_integrals(P policy, Real smoothing_length) {
    kernel_weight.resize(packages() * package_points<D>);
    kernel_gradient.resize(packages() * package_points<D>);
    View<Real> weight = kernel_weight.write(policy);
    View<Vec<Real, D>> gradient = kernel_gradient.write(policy);
    particle_for(policy, Index(far_field_packages) * package_points<D>,
                 level_set_kernels::FarFieldKernelIntegrals<D>{weight, gradient});
    const Real dx = grid().data_spacing;
    const auto kernel = WendlandC2Kernel<Real, D>::from_spacing(
        smoothing_length / WendlandC2Kernel<Real, D>::smoothing_length_ratio);
    data_point_for(policy, mesh,
                   KernelIntegralsAtDataPoints<D>{phi.read(policy), normal.read(policy), mesh.neighbourhood.read(policy),
                                                  weight, gradient, HalfSpaceKernelIntegral<D>{kernel}, dx,
                                                  sub_cell_lattice_sum<D>(kernel, dx)});
    fence(policy);
  }

  template <ExecutionPolicy P>
  LevelSetLayerView<D> view(P policy) {
    return {grid(),
            mesh.cell_package.read(policy),
            phi.read(policy),
            normal.read(policy),
            kernel_weight.read(policy),
            kernel_gradient.read(policy),
            far_field_distance};
  }

  // Bytes per data point of what a probe and the stencils need: phi, the cell -> package
  // index, the package metadata (cell, type, neighbourhood); the normal and the tags apart.
  double bytes_per_data_point() const {
    const double per_package = double(package_points<D>) * sizeof(Real) + sizeof(std::uint64_t) +
                               sizeof(PackageType) + sizeof(PackageNeighbourhood<D>);
    const double total = per_package * double(packages()) + double(grid().cell_count()) * sizeof(std::uint32_t);
    return total / (double(data_packages()) * package_points<D>);
  }

  PackageMesh<D> mesh;
  DiscreteVariable<CellTag> tags;       // outside, inside, inner or core
  DiscreteVariable<CellTag> cell_side;  // before inner tagging: core, or the side of a cell without surface
  // Host policies, triangle meshes: per package, the next layer's tags of its cell's 8 children and
  // their centres' squared distances (SignedDistanceInPackages); dropped once that layer is built.
  DiscreteVariable<CellTag> children_tag{"LevelSetChildrenTag"};
  DiscreteVariable<float> children_distance2{"LevelSetChildrenDistance2"};
  DiscreteVariable<Real> phi{"LevelSetPhi"};
  DiscreteVariable<Vec<Real, D>> normal{"LevelSetNormal"};
  DiscreteVariable<Real> kernel_weight{"LevelSetKernelWeight"};
  DiscreteVariable<Vec<Real, D>> kernel_gradient{"LevelSetKernelGradient"};
  Real far_field_distance;
};

}  // namespace unisph
