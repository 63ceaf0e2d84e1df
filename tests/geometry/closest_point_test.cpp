// Closest points on a triangle and a segment, feature by feature, and the solid angle /
// segment angle of the winding number, on every policy.
#include <cmath>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/geometry/closest_point.hpp"
#include "unisph/geometry/winding_number.hpp"

namespace {
using namespace unisph;
using Vec3 = Vec<Real, 3>;
using Vec2 = Vec<Real, 2>;

// The triangle (0,0,0), (2,0,0), (0,2,0) and one query point per Voronoi region.
struct TriangleCase {
  Vec3 p, expected;
  Feature feature;
};
const std::vector<TriangleCase> triangle_cases = {
    {{{0.5, 0.5, 1}}, {{0.5, 0.5, 0}}, Feature::face},
    {{{1, -1, 0.5}}, {{1, 0, 0}}, Feature::edge0},
    {{{2, 2, -1}}, {{1, 1, 0}}, Feature::edge1},
    {{{-1, 1, 0}}, {{0, 1, 0}}, Feature::edge2},
    {{{-1, -1, 3}}, {{0, 0, 0}}, Feature::vertex0},
    {{{3, -1, 0}}, {{2, 0, 0}}, Feature::vertex1},
    {{{-0.5, 3, 1}}, {{0, 2, 0}}, Feature::vertex2},
};

struct TriangleKernel {
  View<const Vec3> points;
  View<Vec3> closest;
  View<int> feature;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    const ClosestPoint<Real, 3> c =
        closest_point_on_triangle(points[i], Vec3{{0, 0, 0}}, Vec3{{2, 0, 0}}, Vec3{{0, 2, 0}});
    closest[i] = c.point;
    feature[i] = int(c.feature);
  }
};

struct AngleKernel {
  View<const Vec3> points;
  View<Real> tetrahedron_solid_angle, square_angle;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    // An outward tetrahedron: its solid angles sum to 4π inside and 0 outside.
    const Vec3 a{{0, 0, 0}}, b{{1, 0, 0}}, c{{0, 1, 0}}, d{{0, 0, 1}};
    const Vec3 p = points[i];
    tetrahedron_solid_angle[i] = solid_angle(p, a, c, b) + solid_angle(p, a, b, d) + solid_angle(p, a, d, c) +
                                 solid_angle(p, b, c, d);
    // The counter-clockwise unit square in the xy plane: 2π inside, 0 outside.
    const Vec2 q{{p[0], p[1]}}, s0{{0, 0}}, s1{{1, 0}}, s2{{1, 1}}, s3{{0, 1}};
    square_angle[i] = subtended_angle(q, s0, s1) + subtended_angle(q, s1, s2) + subtended_angle(q, s2, s3) +
                      subtended_angle(q, s3, s0);
  }
};

UNISPH_POLICY_TEST_SUITE(ClosestPointTest);

TYPED_TEST(ClosestPointTest, EveryVoronoiRegionOfATriangle) {
  std::vector<Vec3> points;
  for (const TriangleCase& c : triangle_cases) points.push_back(c.p);
  DiscreteVariable<Vec3> p("Points");
  p.assign(points);
  DiscreteVariable<Vec3> closest("Closest", points.size());
  DiscreteVariable<int> feature("Feature", points.size());
  particle_for(this->policy, points.size(), TriangleKernel{p.read(this->policy), closest.write(this->policy), feature.write(this->policy)});
  const std::vector<Vec3> got = closest.to_vector();
  const std::vector<int> got_feature = feature.to_vector();
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[i][k], triangle_cases[i].expected[k], 1e-6) << "case " << i;
    EXPECT_EQ(got_feature[i], int(triangle_cases[i].feature)) << "case " << i;
  }
}

TYPED_TEST(ClosestPointTest, SolidAnglesAndSegmentAnglesSumToWindingNumbers) {
  const std::vector<Vec3> points = {{{0.1, 0.1, 0.1}}, {{0.2, 0.3, 0.4}}, {{2, 2, 2}}, {{-1, 0.5, 0.2}}, {{0.5, 0.5, -3}}};
  const std::vector<bool> in_tetrahedron = {true, true, false, false, false};
  const std::vector<bool> in_square = {true, true, false, false, true};
  DiscreteVariable<Vec3> p("Points");
  p.assign(points);
  DiscreteVariable<Real> tet("TetrahedronAngle", points.size()), square("SquareAngle", points.size());
  particle_for(this->policy, points.size(), AngleKernel{p.read(this->policy), tet.write(this->policy), square.write(this->policy)});
  const std::vector<Real> t = tet.to_vector(), s = square.to_vector();
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_NEAR(t[i] / (4 * pi<Real>()), in_tetrahedron[i] ? 1.0 : 0.0, 1e-5) << i;
    EXPECT_NEAR(s[i] / (2 * pi<Real>()), in_square[i] ? 1.0 : 0.0, 1e-5) << i;
  }
}

TEST(HostClosestPoint, DegenerateTrianglesAndSegments) {
  // Collinear corners: the nearest point of the segment they span.
  const auto c = closest_point_on_triangle(Vec3{{1, 1, 0}}, Vec3{{0, 0, 0}}, Vec3{{1, 0, 0}}, Vec3{{2, 0, 0}});
  EXPECT_NEAR(squared_norm(c.point - Vec3{{1, 0, 0}}), 0.0, 1e-12);
  // All three corners in one point.
  const auto d = closest_point_on_triangle(Vec3{{1, 1, 1}}, Vec3{{0, 0, 0}}, Vec3{{0, 0, 0}}, Vec3{{0, 0, 0}});
  EXPECT_EQ(d.point, (Vec3{{0, 0, 0}}));
  // Segments: both ends and the interior.
  EXPECT_EQ(closest_point_on_segment(Vec2{{-1, 1}}, Vec2{{0, 0}}, Vec2{{2, 0}}).feature, Feature::vertex0);
  EXPECT_EQ(closest_point_on_segment(Vec2{{3, 1}}, Vec2{{0, 0}}, Vec2{{2, 0}}).feature, Feature::vertex1);
  const auto m = closest_point_on_segment(Vec2{{0.5, 1}}, Vec2{{0, 0}}, Vec2{{2, 0}});
  EXPECT_EQ(m.feature, Feature::edge0);
  EXPECT_EQ(m.point, (Vec2{{0.5, 0}}));
}

}  // namespace
