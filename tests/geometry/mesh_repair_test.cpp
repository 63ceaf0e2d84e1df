// Welding, removal of degenerate and duplicate facets, and outward orientation per closed component.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "test_data.hpp"
#include "unisph/geometry/mesh_repair.hpp"

namespace {
using namespace unisph;
using unisph::testing::test_data;
using V = Vec<double, 3>;

RawTriangle facet(V a, V b, V c) { return {{a, b, c}}; }

// An outward tetrahedron with corners o, o+s x, o+s y, o+s z; `inward` writes it inside-out.
std::vector<RawTriangle> tetrahedron(V o, double s, bool inward = false) {
  const V a = o, b = o + V{{s, 0, 0}}, c = o + V{{0, s, 0}}, d = o + V{{0, 0, s}};
  std::vector<RawTriangle> f = {facet(a, c, b), facet(a, b, d), facet(a, d, c), facet(b, c, d)};
  if (inward)
    for (RawTriangle& t : f) std::swap(t.corner[1], t.corner[2]);
  return f;
}

LoadedMesh repair(const std::vector<RawTriangle>& facets) {
  StlFacets stl;
  stl.binary = true;
  stl.solids = 1;
  stl.facets = facets;
  return repair_triangle_mesh(stl, "test");
}

TEST(HostMeshRepair, ClosedTestMeshesAreClosedAndOutward) {
  for (const char* file : {"teapot.stl", "trimesh_unit_sphere.stl", "triangle_prism.stl", "barrel.stl",
                           "trimesh_20mm-xyz-cube.stl", "trimesh_cylinder.stl", "trimesh_plate_holes.stl",
                           "SPHinXsys.stl", "trimesh_two_objects_mixed_case_names.stl", "trimesh_multibody.stl"}) {
    const LoadedMesh loaded = load_triangle_mesh(test_data(std::string("geometry/") + file));
    const MeshReport& r = loaded.report;
    EXPECT_TRUE(r.closed()) << file << ": " << r.boundary_edges << " boundary, " << r.non_manifold_edges
                            << " non-manifold edges";
    EXPECT_TRUE(r.consistently_oriented) << file;
    EXPECT_GT(r.divergence_volume, 0.0) << file;
  }
}

TEST(HostMeshRepair, UnitSphereWeldsToEulerCountsAndItsVolume) {
  const LoadedMesh loaded = load_triangle_mesh(test_data("geometry/trimesh_unit_sphere.stl"));
  EXPECT_EQ(loaded.mesh.triangles.size(), 1280u);
  EXPECT_EQ(loaded.report.welded_vertices, 642u);  // V = F / 2 + 2 for a closed genus-0 surface
  EXPECT_EQ(loaded.report.corners_read, 3840u);
  EXPECT_NEAR(loaded.report.divergence_volume, 4.1527, 1e-4);
  EXPECT_TRUE(loaded.report.components_turned_outward.empty());
}

TEST(HostMeshRepair, DegenerateAndDuplicateFacetsAreRemovedAndCounted) {
  std::vector<RawTriangle> facets = tetrahedron(V{}, 1.0);
  facets.push_back(facets[1]);                                                // duplicate
  facets.push_back(facet(facets[2].corner[0], facets[2].corner[2], facets[2].corner[1]));  // reversed duplicate
  facets.push_back(facet(V{{0, 0, 0}}, V{{0, 0, 0}}, V{{1, 0, 0}}));            // two corners welded
  facets.push_back(facet(V{{0, 0, 0}}, V{{0.5, 0, 0}}, V{{1, 0, 0}}));          // zero area
  facets.push_back(facet(V{{-0.0, 0, 0}}, V{{0, 1, 0}}, V{{0, 0, 1}}));         // -0 welds to 0: a duplicate
  const LoadedMesh loaded = repair(facets);
  EXPECT_EQ(loaded.report.facets_read, 9u);
  EXPECT_EQ(loaded.report.duplicate_facets_removed, 3u);
  EXPECT_EQ(loaded.report.degenerate_facets_removed, 2u);
  EXPECT_EQ(loaded.mesh.triangles.size(), 4u);
  EXPECT_EQ(loaded.report.welded_vertices, 4u);
  EXPECT_TRUE(loaded.report.closed());
  EXPECT_NEAR(loaded.report.divergence_volume, 1.0 / 6.0, 1e-15);
}

TEST(HostMeshRepair, InsideOutBodyIsTurnedAndReported) {
  std::vector<RawTriangle> facets = tetrahedron(V{}, 1.0);
  const std::vector<RawTriangle> inward = tetrahedron(V{{5, 0, 0}}, 2.0, true);
  facets.insert(facets.end(), inward.begin(), inward.end());
  const LoadedMesh loaded = repair(facets);
  EXPECT_EQ(loaded.report.components, 2u);
  EXPECT_EQ(loaded.report.closed_components, 2u);
  EXPECT_EQ(loaded.report.components_turned_outward, std::vector<std::size_t>{1});
  EXPECT_NEAR(loaded.report.divergence_volume, 1.0 / 6.0 + 8.0 / 6.0, 1e-12);
}

TEST(HostMeshRepair, InconsistentTrianglesAreTurnedToTheMajority) {
  std::vector<RawTriangle> facets = tetrahedron(V{}, 1.0);
  std::swap(facets[3].corner[0], facets[3].corner[1]);
  const LoadedMesh loaded = repair(facets);
  EXPECT_FALSE(loaded.report.consistently_oriented_as_read);
  EXPECT_TRUE(loaded.report.consistently_oriented);
  EXPECT_EQ(loaded.report.triangles_flipped_for_consistency, 1u);
  EXPECT_TRUE(loaded.report.components_turned_outward.empty());
  EXPECT_NEAR(loaded.report.divergence_volume, 1.0 / 6.0, 1e-15);
}

TEST(HostMeshRepair, HalfAndHalfClosedBodyTakesTheOutwardHalf) {
  // Two of four triangles written the other way: no majority, so the half that leaves the
  // tetrahedron outward is turned, and it is not reported as turned outward.
  std::vector<RawTriangle> facets = tetrahedron(V{}, 1.0);
  for (int t : {0, 1}) std::swap(facets[t].corner[1], facets[t].corner[2]);
  const LoadedMesh loaded = repair(facets);
  EXPECT_EQ(loaded.report.triangles_flipped_for_consistency, 2u);
  EXPECT_TRUE(loaded.report.components_turned_outward.empty());
  EXPECT_NEAR(loaded.report.divergence_volume, 1.0 / 6.0, 1e-15);
}

TEST(HostMeshRepair, NestedBodyBecomesACavity) {
  // A small outward tetrahedron inside a large one: the inner one bounds a cavity, so it must
  // face into it (negative volume), and the total is the difference.
  std::vector<RawTriangle> facets = tetrahedron(V{}, 10.0);
  const std::vector<RawTriangle> inner = tetrahedron(V{{1, 1, 1}}, 1.0);
  facets.insert(facets.end(), inner.begin(), inner.end());
  const LoadedMesh loaded = repair(facets);
  EXPECT_EQ(loaded.report.components_turned_outward, std::vector<std::size_t>{1});
  EXPECT_NEAR(loaded.report.divergence_volume, 1000.0 / 6.0 - 1.0 / 6.0, 1e-10);
}

TEST(HostMeshRepair, MultibodyFileHasItsInwardBodyTurned) {
  const LoadedMesh loaded = load_triangle_mesh(test_data("geometry/trimesh_multibody.stl"));
  EXPECT_EQ(loaded.report.format, "ASCII STL");
  // As read, bodyB (component 0) has 2 of its 12 triangles facing out and 10 facing in; bodyA
  // (component 1) 4 of 20 out and 16 in. The minorities are turned to agree (6 triangles), which
  // leaves both bodies inside-out, so both are turned outward. Checked independently: every
  // edge is then used once in each direction, and the volumes are 0.00147 and 0.00595.
  EXPECT_EQ(loaded.report.components, 2u);
  EXPECT_FALSE(loaded.report.consistently_oriented_as_read);
  EXPECT_EQ(loaded.report.triangles_flipped_for_consistency, 6u);
  EXPECT_EQ(loaded.report.components_turned_outward, (std::vector<std::size_t>{0, 1}));
  EXPECT_NEAR(loaded.report.divergence_volume, 0.00147143 + 0.00595179, 1e-7);
  EXPECT_TRUE(loaded.report.closed());
  EXPECT_TRUE(loaded.report.consistently_oriented);
  EXPECT_GT(loaded.report.divergence_volume, 0.0019853 + 0.005);
}

TEST(HostMeshRepair, OpenMeshesReportTheirBoundary) {
  const LoadedMesh teapot = load_triangle_mesh(test_data("geometry/trimesh_teapot.stl"));
  EXPECT_FALSE(teapot.report.closed());
  EXPECT_EQ(teapot.report.boundary_edges, 64u);
  const LoadedMesh soup = load_triangle_mesh(test_data("geometry/trimesh_soup.stl"));
  EXPECT_FALSE(soup.report.closed());
  EXPECT_EQ(soup.report.boundary_edges, 300u);
  EXPECT_EQ(soup.report.closed_components, 0u);
}

}  // namespace
