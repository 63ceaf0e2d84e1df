// Package mesh: allocation from tags on every policy (same layout as seq, Morton order),
// consistent cell <-> package maps and neighbourhoods, and neighbour_index_shift reading a
// linear field across package borders.
#include <cstdint>
#include <limits>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/grid/package_for.hpp"
#include "unisph/grid/package_mesh.hpp"

namespace {
using namespace unisph;

PackageGrid<3> test_grid() { return PackageGrid<3>{Vec<Real, 3>{{-1.0, -2.0, 0.5}}, Real(0.125), Vec<int, 3>{{13, 11, 9}}}; }

// Core where a spherical shell passes, inner around it, the rest inside or outside.
std::vector<CellTag> shell_tags(const PackageGrid<3>& grid) {
  std::vector<CellTag> tags(grid.cell_count());
  const Vec<Real, 3> centre{{-1.0 + 6.5 * 0.5, -2.0 + 5.5 * 0.5, 0.5 + 4.5 * 0.5}};
  for (Index c = 0; c < tags.size(); ++c) {
    const Real r = norm(grid.cell_centre(grid.coordinates(c)) - centre);
    tags[c] = r < 1.2 ? CellTag::inside : CellTag::outside;
    if (r > 1.2 - 0.5 && r < 1.2 + 0.5) tags[c] = CellTag::core;
    else if (r > 1.2 - 1.0 && r < 1.2 + 1.0) tags[c] = CellTag::inner;
  }
  return tags;
}

struct Layout {
  std::vector<std::uint32_t> cell_package;
  std::vector<std::uint64_t> package_cell;
  std::vector<PackageType> type;
  std::vector<PackageNeighbourhood<3>> neighbourhood;
};

template <class P>
Layout build(P policy, PackageMesh<3>& mesh) {
  DiscreteVariable<CellTag> tags("Tags");
  const std::vector<CellTag> host = shell_tags(mesh.grid());
  tags.assign(host);
  mesh.allocate(policy, tags);
  return {mesh.cell_package.to_vector(), mesh.package_cell.to_vector(), mesh.package_type.to_vector(),
          mesh.neighbourhood.to_vector()};
}

// value = a . global data point position: linear, so every stencil can check it exactly.
struct WriteLinearField {
  PackageGrid<3> grid;
  View<const std::uint64_t> package_cell;
  View<Real> field;
  UNISPH_HOST_DEVICE void operator()(std::uint32_t package, int local) const {
    const Vec<Real, 3> x = grid.data_position(grid.coordinates(package_cell[package]), local);
    field[Index(package) * package_points<3> + local] = x[0] + 2 * x[1] - 3 * x[2];
  }
};

// For each data point, the largest error of the field read at every relative index in the
// 3^3 packages around through neighbour_index_shift, where that neighbour has data.
struct CheckShift {
  PackageGrid<3> grid;
  View<const std::uint64_t> package_cell;
  View<const PackageNeighbourhood<3>> neighbourhood;
  View<const Real> field;
  View<Real> error;
  UNISPH_HOST_DEVICE void operator()(std::uint32_t package, int local) const {
    const Vec<int, 3> cell = grid.coordinates(package_cell[package]);
    Real worst = 0;
    // Read a 3x3x3 block around each point, offset by the point's own local index, so that
    // points near a border look into every neighbour.
    const Vec<int, 3> own{{local % 4, (local / 4) % 4, local / 16}};
    for (int dz = -4; dz <= 4; dz += 2)
      for (int dy = -4; dy <= 4; dy += 2)
        for (int dx = -4; dx <= 4; dx += 2) {
          const Vec<int, 3> relative{{own[0] + dx, own[1] + dy, own[2] + dz}};
          bool inside_range = true;
          for (int k = 0; k < 3; ++k) inside_range = inside_range && relative[k] >= -4 && relative[k] < 8;
          if (!inside_range) continue;
          const DataPointAddress a = neighbour_index_shift<3>(relative, neighbourhood[package]);
          if (a.package < far_field_packages) continue;
          const Vec<int, 3> point{{4 * cell[0] + relative[0], 4 * cell[1] + relative[1], 4 * cell[2] + relative[2]}};
          const Vec<Real, 3> x = grid.data_position(point);
          const Real expected = x[0] + 2 * x[1] - 3 * x[2];
          const Real got = field[Index(a.package) * package_points<3> + a.local_point];
          const Real e = got > expected ? got - expected : expected - got;
          worst = e > worst ? e : worst;
        }
    error[Index(package) * package_points<3> + local] = worst;
  }
};

UNISPH_POLICY_TEST_SUITE(PackageMeshTest);

TYPED_TEST(PackageMeshTest, SameLayoutAsSeqInMortonOrder) {
  PackageMesh<3> reference_mesh(test_grid()), mesh(test_grid());
  const Layout reference = build(seq, reference_mesh);
  const Layout layout = build(this->policy, mesh);
  EXPECT_EQ(layout.cell_package, reference.cell_package);
  EXPECT_EQ(layout.package_cell, reference.package_cell);
  EXPECT_EQ(layout.type, reference.type);
  ASSERT_EQ(layout.neighbourhood.size(), reference.neighbourhood.size());
  for (Index p = 0; p < layout.neighbourhood.size(); ++p)
    for (int s = 0; s < 27; ++s) ASSERT_EQ(layout.neighbourhood[p].package[s], reference.neighbourhood[p].package[s]);

  const PackageGrid<3> grid = test_grid();
  const std::vector<CellTag> tags = shell_tags(grid);
  Index expected_packages = 0;
  for (CellTag t : tags) expected_packages += has_package(t);
  ASSERT_EQ(mesh.data_packages(), expected_packages);
  ASSERT_GT(expected_packages, 100u);
  for (Index p = far_field_packages; p + 1 < mesh.packages(); ++p)
    EXPECT_LT(morton_key<3>(grid.coordinates(layout.package_cell[p])),
              morton_key<3>(grid.coordinates(layout.package_cell[p + 1])));
  for (Index c = 0; c < tags.size(); ++c) {
    const std::uint32_t p = layout.cell_package[c];
    if (has_package(tags[c])) {
      ASSERT_EQ(layout.package_cell[p], c);
      EXPECT_EQ(std::uint8_t(layout.type[p]), std::uint8_t(tags[c]));
    } else {
      EXPECT_EQ(p, tags[c] == CellTag::inside ? inside_package : outside_package);
    }
  }
  for (std::uint32_t f = 0; f < far_field_packages; ++f)
    for (int s = 0; s < 27; ++s) EXPECT_EQ(layout.neighbourhood[f].package[s], f);
}

TYPED_TEST(PackageMeshTest, IndexShiftReadsAcrossPackageBorders) {
  PackageMesh<3> mesh(test_grid());
  build(this->policy, mesh);
  const auto policy = this->policy;
  DiscreteVariable<Real> field("Field", mesh.packages() * package_points<3>);
  DiscreteVariable<Real> error("Error", mesh.packages() * package_points<3>);
  data_point_for(policy, mesh, WriteLinearField{mesh.grid(), mesh.package_cell.read(policy), field.write(policy)});
  data_point_for(policy, mesh,
                 CheckShift{mesh.grid(), mesh.package_cell.read(policy), mesh.neighbourhood.read(policy),
                            field.read(policy), error.write(policy)});
  Real worst = 0;
  for (Real e : error.to_vector()) worst = e > worst ? e : worst;
  EXPECT_LT(worst, Real(64) * std::numeric_limits<Real>::epsilon() * 16);
}

}  // namespace
