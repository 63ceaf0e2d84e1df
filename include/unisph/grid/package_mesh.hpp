#pragma once
// A mesh of data packages: the background cells of a PackageGrid, the packages owned by the
// cells tagged inner or core, and what kernels need to find them:
//
//   cell_package    per cell: its package (0 / 1: the outside / inside far-field package)
//   package_cell    per package: the linear index of its cell (far-field packages: all ones)
//   package_type    per package: far field, inner or core
//   neighbourhood   per package: the 3^D packages around it (far-field packages: themselves;
//                   beyond the grid: the outside package)
//
// allocate(policy, tags) builds all of it from per-cell tags on any policy. Packages are
// ordered by the Morton key of their cell, which is unique, so the layout is the same on every
// policy and every run however the tags were computed, and packages near in space are near in
// memory. Variables defined on packages (values at data points) are DiscreteVariables of
// packages() * 4^D elements, package p's points at [p * 4^D, (p + 1) * 4^D).

#include <cstdint>
#include <limits>

#include "unisph/exec/algorithms.hpp"
#include "unisph/grid/cell_tag.hpp"
#include "unisph/grid/neighbour_index_shift.hpp"
#include "unisph/grid/package_grid.hpp"
#include "unisph/memory/discrete_variable.hpp"
#include "unisph/core/morton_key.hpp"

namespace unisph {

namespace package_mesh_kernels {
struct FlagPackages {
  View<const CellTag> tags;
  View<std::uint32_t> flags;
  UNISPH_HOST_DEVICE void operator()(Index c) const { flags[c] = has_package(tags[c]) ? 1u : 0u; }
};
struct CountFlags {
  View<const std::uint32_t> flags;
  UNISPH_HOST_DEVICE Index operator()(Index c) const { return flags[c]; }
};
template <int D>
struct ScatterPackages {
  PackageGrid<D> grid;
  View<const CellTag> tags;
  View<const std::uint32_t> offsets;
  View<std::uint64_t> keys;          // one per data package
  View<std::uint64_t> package_cell;  // one per data package (past the far-field ones)
  UNISPH_HOST_DEVICE void operator()(Index c) const {
    if (!has_package(tags[c])) return;
    const std::uint32_t slot = offsets[c];
    keys[slot] = morton_key<D>(grid.coordinates(c));
    package_cell[slot] = c;
  }
};
struct FarFieldCells {
  View<const CellTag> tags;
  View<std::uint32_t> cell_package;
  UNISPH_HOST_DEVICE void operator()(Index c) const {
    if (!has_package(tags[c])) cell_package[c] = tags[c] == CellTag::inside ? inside_package : outside_package;
  }
};
struct PackageCells {
  View<const CellTag> tags;
  View<std::uint64_t> package_cell;
  View<std::uint32_t> cell_package;
  View<PackageType> package_type;
  UNISPH_HOST_DEVICE void operator()(Index p) const {
    if (p < far_field_packages) {
      package_type[p] = PackageType::far_field;
      package_cell[p] = ~std::uint64_t(0);
      return;
    }
    const Index c = package_cell[p];
    cell_package[c] = std::uint32_t(p);
    package_type[p] = tags[c] == CellTag::core ? PackageType::core : PackageType::inner;
  }
};
template <int D>
struct Neighbourhoods {
  PackageGrid<D> grid;
  View<const std::uint64_t> package_cell;
  View<const std::uint32_t> cell_package;
  View<PackageNeighbourhood<D>> neighbourhood;
  UNISPH_HOST_DEVICE void operator()(Index p) const {
    PackageNeighbourhood<D> result;
    if (p < far_field_packages) {
      for (int s = 0; s < neighbourhood_size<D>; ++s) result.package[s] = std::uint32_t(p);
      neighbourhood[p] = result;
      return;
    }
    const Vec<int, D> cell = grid.coordinates(package_cell[p]);
    for (int s = 0; s < neighbourhood_size<D>; ++s) {
      const Vec<int, D> other = neighbour_in_block<D>(cell, s);
      result.package[s] = grid.contains(other) ? cell_package[grid.linear(other)] : outside_package;
    }
    neighbourhood[p] = result;
  }
};
}  // namespace package_mesh_kernels

template <int D>
class PackageMesh {
 public:
  static constexpr int dimension = D;

  explicit PackageMesh(const PackageGrid<D>& grid) : grid_(grid) {}

  const PackageGrid<D>& grid() const { return grid_; }
  // Every package, the two far-field ones included.
  Index packages() const { return packages_; }
  Index data_packages() const { return packages_ - far_field_packages; }

  // Allocates a package for every cell tagged inner or core (tags: one per cell of the grid).
  template <ExecutionPolicy P>
  void allocate(P policy, DiscreteVariable<CellTag>& tags) {
    namespace k = package_mesh_kernels;
    const Index cells = grid_.cell_count();
    if (tags.size() != cells) throw Error("PackageMesh::allocate: one tag per cell is needed");
    View<const CellTag> tag = tags.read(policy);
    // One array per cell: the flags, then (scanned in place) each package's slot.
    DiscreteVariable<std::uint32_t> offsets("PackageOffsets", cells);
    particle_for(policy, cells, k::FlagPackages{tag, offsets.write(policy)});
    const Index count = particle_reduce(policy, cells, Sum<Index>{}, k::CountFlags{offsets.read(policy)});
    exclusive_scan(policy, offsets, offsets);
    if (count + far_field_packages > std::numeric_limits<std::uint32_t>::max())
      throw Error("PackageMesh::allocate: more packages than 32-bit package indices can address");
    packages_ = count + far_field_packages;

    DiscreteVariable<std::uint64_t> keys("PackageKeys", count);
    package_cell.resize(packages_);
    View<std::uint64_t> cell_of = package_cell.write(policy);
    particle_for(policy, cells,
                 k::ScatterPackages<D>{grid_, tag, offsets.read(policy), keys.write(policy),
                                       cell_of.subview(far_field_packages, count)});
    int max_cells = 1;
    for (int a = 0; a < D; ++a) max_cells = grid_.cells[a] > max_cells ? grid_.cells[a] : max_cells;
    sort_pairs(policy, keys.read_write(policy), cell_of.subview(far_field_packages, count), 0,
               morton_key_bits(D, max_cells));

    cell_package.resize(cells);
    package_type.resize(packages_);
    neighbourhood.resize(packages_);
    View<std::uint32_t> cell_pkg = cell_package.write(policy);
    particle_for(policy, cells, k::FarFieldCells{tag, cell_pkg});
    particle_for(policy, packages_, k::PackageCells{tag, cell_of, cell_pkg, package_type.write(policy)});
    particle_for(policy, packages_,
                 k::Neighbourhoods<D>{grid_, cell_of, cell_pkg, neighbourhood.write(policy)});
    fence(policy);
  }

  DiscreteVariable<std::uint32_t> cell_package{"CellPackage"};
  DiscreteVariable<std::uint64_t> package_cell{"PackageCell"};
  DiscreteVariable<PackageType> package_type{"PackageType"};
  DiscreteVariable<PackageNeighbourhood<D>> neighbourhood{"PackageNeighbourhood"};

 private:
  PackageGrid<D> grid_;
  Index packages_ = far_field_packages;
};

}  // namespace unisph
