// package_for and data_point_for (grid/package_for.hpp), which walk the packages -> data points
// hierarchy with iter::View on every policy (one worker per package on the host, a team of 4^D
// threads per package on the GPU): every data package and every data point visited exactly once,
// with the indices a plain loop gives, in 2D and 3D, on meshes whose package count does not fill
// whole CUDA blocks, and on empty meshes (never allocated, or no cell with a package).
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/exec/atomic.hpp"
#include "unisph/grid/package_for.hpp"
#include "unisph/grid/package_mesh.hpp"

namespace {
using namespace unisph;

// Per package: how often package_for visited it; a count of calls with an index out of range.
struct MarkPackage {
  Index packages;
  View<unsigned> marks;
  View<unsigned> wrong;
  UNISPH_HOST_DEVICE void operator()(std::uint32_t package) const {
    if (Index(package) >= packages) {
      atomic_add(&wrong[0], 1u);
      return;
    }
    atomic_add(&marks[package], 1u);
  }
};

// Per data point: how often data_point_for visited it, and what it was told (package * 4^D + local).
template <int D>
struct MarkDataPoint {
  Index packages;
  View<unsigned> marks;
  View<long long> told;
  View<unsigned> wrong;
  UNISPH_HOST_DEVICE void operator()(std::uint32_t package, int local) const {
    if (Index(package) >= packages || local < 0 || local >= package_points<D>) {
      atomic_add(&wrong[0], 1u);
      return;
    }
    const Index k = Index(package) * package_points<D> + Index(local);
    atomic_add(&marks[k], 1u);
    told[k] = (long long)package * package_points<D> + local;
  }
};

// Core cells in a ball of radius r around the centre of the box, inner around them.
template <int D>
std::vector<CellTag> ball_tags(const PackageGrid<D>& grid, double r) {
  std::vector<CellTag> tags(grid.cell_count(), CellTag::outside);
  for (Index c = 0; c < tags.size(); ++c) {
    const Vec<int, D> x = grid.coordinates(c);
    double d2 = 0;
    for (int k = 0; k < D; ++k) {
      const double dx = x[k] + 0.5 - 0.5 * grid.cells[k];
      d2 += dx * dx;
    }
    if (d2 < r * r) tags[c] = CellTag::core;
    else if (d2 < (r + 1.5) * (r + 1.5)) tags[c] = CellTag::inner;
    else if (d2 < (r + 3) * (r + 3)) tags[c] = CellTag::inside;
  }
  return tags;
}

template <int D, class P>
void check_loops(P policy, PackageMesh<D>& mesh, const std::string& where) {
  constexpr Index points = package_points<D>;
  const Index packages = mesh.packages();
  DiscreteVariable<unsigned> package_marks("package_marks", packages), point_marks("point_marks", packages * points);
  DiscreteVariable<long long> told("told", packages * points);
  DiscreteVariable<unsigned> wrong("wrong", 2);
  package_for(policy, mesh, MarkPackage{packages, package_marks.read_write(policy), wrong.read_write(policy).subview(0, 1)});
  data_point_for(policy, mesh,
                 MarkDataPoint<D>{packages, point_marks.read_write(policy), told.read_write(policy),
                                  wrong.read_write(policy).subview(1, 1)});
  fence(policy);

  // The plain loops: packages 2 .. packages - 1, each with its points 0 .. 4^D - 1.
  std::vector<unsigned> expected_packages(packages, 0u), expected_points(packages * points, 0u);
  std::vector<long long> expected_told(packages * points, 0);
  for (Index p = far_field_packages; p < packages; ++p) {
    expected_packages[p] = 1;
    for (Index l = 0; l < points; ++l) {
      expected_points[p * points + l] = 1;
      expected_told[p * points + l] = (long long)(p * points + l);
    }
  }
  EXPECT_EQ(wrong.to_vector(), (std::vector<unsigned>{0u, 0u})) << where << ": calls with an index out of range";
  EXPECT_EQ(package_marks.to_vector(), expected_packages) << where << ": package_for";
  EXPECT_EQ(point_marks.to_vector(), expected_points) << where << ": data_point_for";
  EXPECT_EQ(told.to_vector(), expected_told) << where << ": data_point_for's (package, local point)";
}

UNISPH_POLICY_TEST_SUITE(PackageLoops);

// check_loops over the packages of balls of the given radii on `grid`.
template <int D, class P>
void check_balls(P policy, const PackageGrid<D>& grid, std::initializer_list<double> radii) {
  for (const double r : radii) {
    PackageMesh<D> mesh(grid);
    DiscreteVariable<CellTag> tags("Tags");
    tags.assign(ball_tags(mesh.grid(), r));
    mesh.allocate(policy, tags);
    ASSERT_GT(mesh.data_packages(), Index(0));
    check_loops(policy, mesh,
                std::to_string(D) + "D, r = " + std::to_string(r) + ", " + std::to_string(mesh.data_packages()) + " packages");
  }
}

TYPED_TEST(PackageLoops, VisitEveryPackageAndDataPointOnceIn3D) {
  // Package counts around and not on multiples of the 4 teams of a CUDA block.
  check_balls(this->policy, PackageGrid<3>{Vec<Real, 3>{{-1.0, 0.0, 0.5}}, Real(0.125), Vec<int, 3>{{13, 11, 9}}},
              {0.6, 1.2, 2.5, 4.0});
}

TYPED_TEST(PackageLoops, VisitEveryPackageAndDataPointOnceIn2D) {
  // 2D packages have 16 points: 16 teams of 16 per CUDA block.
  check_balls(this->policy, PackageGrid<2>{Vec<Real, 2>{{0.0, -1.0}}, Real(0.25), Vec<int, 2>{{17, 15}}}, {0.6, 2.0, 5.5});
}

TYPED_TEST(PackageLoops, VisitNothingOnEmptyMeshes) {
  {
    PackageMesh<3> never_allocated(PackageGrid<3>{Vec<Real, 3>{{0, 0, 0}}, Real(0.25), Vec<int, 3>{{4, 4, 4}}});
    EXPECT_EQ(never_allocated.data_packages(), Index(0));
    check_loops(this->policy, never_allocated, "3D, never allocated");
  }
  {
    PackageMesh<3> mesh(PackageGrid<3>{Vec<Real, 3>{{0, 0, 0}}, Real(0.25), Vec<int, 3>{{5, 4, 3}}});
    DiscreteVariable<CellTag> tags("Tags");
    tags.assign(std::vector<CellTag>(mesh.grid().cell_count(), CellTag::inside));
    mesh.allocate(this->policy, tags);
    EXPECT_EQ(mesh.data_packages(), Index(0));
    check_loops(this->policy, mesh, "3D, no cell with a package");
  }
  {
    PackageMesh<2> mesh(PackageGrid<2>{Vec<Real, 2>{{0, 0}}, Real(0.25), Vec<int, 2>{{6, 5}}});
    DiscreteVariable<CellTag> tags("Tags");
    tags.assign(std::vector<CellTag>(mesh.grid().cell_count(), CellTag::outside));
    mesh.allocate(this->policy, tags);
    EXPECT_EQ(mesh.data_packages(), Index(0));
    check_loops(this->policy, mesh, "2D, no cell with a package");
  }
}

}  // namespace
