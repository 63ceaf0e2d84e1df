// Polygon files and 2D queries: reading and orientation by nesting, one-line errors, closest
// point against brute force and the sign against the winding number on every policy.
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "support/policy_test.hpp"
#include "test_data.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/geometry/polygon_reader.hpp"
#include "unisph/geometry/polygon_search.hpp"

namespace {
using namespace unisph;
using unisph::testing::test_data;
using Vec2 = Vec<Real, 2>;

std::string parse_error(const std::string& text) {
  try {
    parse_polygons(text, "shape.poly");
  } catch (const GeometryError& e) {
    return e.what();
  }
  return "";
}
void expect_one_line_error(const std::string& text, const std::string& phrase) {
  const std::string message = parse_error(text);
  ASSERT_FALSE(message.empty()) << "no error; expected '" << phrase << "'";
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_EQ(message.rfind("shape.poly: line ", 0), 0u) << message;
  EXPECT_NE(message.find(phrase), std::string::npos) << message;
}

TEST(HostPolygonReader, NotchedPlateWithHolesIsOrientedByNesting) {
  const LoadedPolygons loaded = read_polygons(test_data("geometry/plate_with_holes.poly"));
  const PolygonReport& r = loaded.report;
  EXPECT_EQ(r.loops, 5u);
  EXPECT_EQ(r.depth, (std::vector<int>{0, 1, 1, 2, 0}));
  EXPECT_EQ(r.loops_turned, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(r.repeated_vertices_removed, 2u);
  EXPECT_EQ(loaded.polygons.edges(), 7u + 4 + 4 + 3 + 3);
  // 100 - notch 3 - hole 9 - hole 12 + island 1 + triangle 3.75
  EXPECT_DOUBLE_EQ(r.area, 100.0 - 3.0 - 9.0 - 12.0 + 1.0 + 3.75);
}

TEST(HostPolygonReader, EmptyFileGivesAnEmptySetThatSearchRefuses) {
  const LoadedPolygons loaded = parse_polygons("# nothing here\n\n", "empty.poly");
  EXPECT_TRUE(loaded.polygons.empty());
  EXPECT_EQ(loaded.polygons.loops(), 0u);
  try {
    PolygonSearch search(loaded.polygons);
    ADD_FAILURE() << "an empty polygon set was accepted";
  } catch (const GeometryError& e) {
    EXPECT_NE(std::string(e.what()).find("empty.poly: the polygon set has no edges"), std::string::npos) << e.what();
  }
}

TEST(HostPolygonReader, OneLineErrors) {
  expect_one_line_error("loop\n0 0\n1 0\n", "line 1: loop 0 has 2 distinct vertices");
  expect_one_line_error("loop\n0 0\n1 1\n2 2\n", "line 1: loop 0 has zero area");
  expect_one_line_error("loop\n0 0\n1 zero\n0 1\n", "line 3: expected a number, found 'zero'");
  expect_one_line_error("loop\n0 0\n1 inf\n0 1\n", "line 3: non-finite coordinate 'inf'");
  expect_one_line_error("0 0\nloop\n", "line 1: a vertex before the first 'loop' line");
  expect_one_line_error("loop\n0 0 0\n", "line 2: expected two numbers 'x y', found more");
  expect_one_line_error("loop\n0\n", "line 2: expected two numbers 'x y', found '0'");
  try {
    read_polygons("/nonexistent/shape.poly");
    ADD_FAILURE();
  } catch (const GeometryError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("/nonexistent/shape.poly: cannot open the file", 0), 0u) << e.what();
  }
}

struct PolygonQueryKernel {
  PolygonSearchView search;
  View<const Vec2> points;
  View<Real> squared_distance, winding;
  View<std::uint32_t> edge;
  View<int> sign;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    const NearestEdge n = search.nearest(points[i]);
    squared_distance[i] = n.squared_distance;
    edge[i] = n.edge;
    sign[i] = search.sign(points[i], n);
    winding[i] = search.winding_number(points[i]);
  }
};

UNISPH_POLICY_TEST_SUITE(PolygonSearchTest);

TYPED_TEST(PolygonSearchTest, ClosestPointAndSignAgainstBruteForceAndWindingNumber) {
  const LoadedPolygons loaded = read_polygons(test_data("geometry/plate_with_holes.poly"));
  const PolygonSet& set = loaded.polygons;
  PolygonSearch search(set);
  // Random points over the box enlarged by 20 %, plus every vertex moved slightly (the corners
  // are where the pseudonormal matters).
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec2> points;
  for (int i = 0; i < 20000; ++i)
    points.push_back({{Real(-3 + 21 * unit(random)), Real(-2 + 14 * unit(random))}});
  for (const auto& v : set.vertices)
    for (int k = 0; k < 8; ++k)
      points.push_back({{Real(v[0] + 0.05 * std::cos(k * 0.785 + 0.1)), Real(v[1] + 0.05 * std::sin(k * 0.785 + 0.1))}});
  const Index n = points.size();
  DiscreteVariable<Vec2> p("Points");
  p.assign(points);
  DiscreteVariable<Real> d2("SquaredDistance", n), w("Winding", n);
  DiscreteVariable<std::uint32_t> e("Edge", n);
  DiscreteVariable<int> s("Sign", n);
  particle_for(this->policy, n,
               PolygonQueryKernel{search.view(this->policy), p.read(this->policy), d2.write(this->policy),
                                  w.write(this->policy), e.write(this->policy), s.write(this->policy)});
  const std::vector<Real> got_d2 = d2.to_vector(), got_w = w.to_vector();
  const std::vector<int> got_sign = s.to_vector();
  std::size_t inside = 0;
  for (Index i = 0; i < n; ++i) {
    Real best = std::numeric_limits<Real>::infinity();
    for (std::size_t l = 0; l < set.loops(); ++l)
      for (std::uint32_t k = set.loop_start[l]; k < set.loop_start[l + 1]; ++k) {
        const std::uint32_t next = k + 1 == set.loop_start[l + 1] ? set.loop_start[l] : k + 1;
        const Vec2 a{{Real(set.vertices[k][0]), Real(set.vertices[k][1])}};
        const Vec2 b{{Real(set.vertices[next][0]), Real(set.vertices[next][1])}};
        best = std::min(best, squared_distance(points[i], closest_point_on_segment(points[i], a, b).point));
      }
    ASSERT_NEAR(std::sqrt(got_d2[i]), std::sqrt(best), 4 * std::numeric_limits<Real>::epsilon() * (1 + std::sqrt(best)))
        << "point " << i;
    const Real rounded = std::round(got_w[i]);
    ASSERT_NEAR(got_w[i], rounded, 1e-6) << "closed polygons have integer winding numbers; point " << i;
    ASSERT_EQ(got_sign[i] < 0, rounded > 0.5) << "point " << i << " (" << points[i][0] << ", " << points[i][1] << ")";
    inside += rounded > 0.5;
  }
  EXPECT_GT(inside, n / 10);
}

}  // namespace
