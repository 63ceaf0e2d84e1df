// Shapes on every policy: signed distance of every primitive, boolean and transform against
// independent analytic formulas (bit for bit on dyadic points, where the arithmetic is exact),
// geometry files against brute force within the level set's accuracy, the same values on every
// policy, inside/outside, the lattice fill and wall layers (against make_tank_particles and brute
// force), removal of fluid next to a wall, and bad input.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "support/policy_test.hpp"
#include "test_data.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/geometry/closest_point.hpp"
#include "unisph/geometry/mesh_repair.hpp"
#include "unisph/geometry/polygon_reader.hpp"
#include "unisph/geometry/winding_number.hpp"
#include "unisph/shape/compiled_shape.hpp"
#include "unisph/shape/lattice_particles.hpp"
#include "unisph/solver/tank_particles.hpp"

namespace {
using namespace unisph;
using namespace unisph::shape;
using unisph::testing::test_data;
using V2 = Vec<Real, 2>;
using V3 = Vec<Real, 3>;
constexpr bool single = sizeof(Real) == 4;
constexpr Real roundoff = single ? Real(2e-5) : Real(1e-12);

template <int D>
using Reference = std::function<Real(const Vec<Real, D>&)>;

// ---- independent reference formulas ----
template <int D>
Real box_reference(const Vec<Real, D>& x, const Vec<Real, D>& lo, const Vec<Real, D>& hi) {
  bool outside = false;
  Real squared = 0, depth = std::numeric_limits<Real>::max();
  for (int k = 0; k < D; ++k) {
    const Real c = std::clamp(x[k], lo[k], hi[k]);
    outside = outside || c != x[k];
    squared += (x[k] - c) * (x[k] - c);
    depth = std::min({depth, x[k] - lo[k], hi[k] - x[k]});
  }
  return outside ? std::sqrt(squared) : -depth;
}
template <int D>
Real sphere_reference(const Vec<Real, D>& x, const Vec<Real, D>& c, Real r) {
  return norm(x - c) - r;
}
// The closest point of the solid cylinder, or the nearest face from inside.
Real cylinder_reference(const V3& x, const V3& a, const V3& b, Real r) {
  const V3 u = (b - a) / norm(b - a);
  const Real length = norm(b - a), t = dot(x - a, u);
  const V3 radial = x - a - u * t;
  const Real rho = norm(radial);
  if (t >= 0 && t <= length && rho <= r) return -std::min({r - rho, t, length - t});
  const Real tc = std::clamp(t, Real(0), length);
  const V3 closest = a + u * tc + (rho > r ? radial * (r / rho) : radial);
  return norm(x - closest);
}
template <int D>
Real half_space_reference(const Vec<Real, D>& x, const Vec<Real, D>& p, const Vec<Real, D>& n) {
  return dot(x - p, n / norm(n));
}
// x rotated by -angle about the axis through p (Rodrigues), i.e. the inverse of the shape's rotation.
V3 rotate_back(const V3& x, Real angle, const V3& axis, const V3& p) {
  const V3 k = axis / norm(axis), v = x - p;
  const Real c = std::cos(-angle), s = std::sin(-angle);
  return p + v * c + cross(k, v) * s + k * (dot(k, v) * (1 - c));
}
V2 rotate_back(const V2& x, Real angle, const V2& p) {
  const Real c = std::cos(-angle), s = std::sin(-angle);
  const V2 v = x - p;
  return p + V2{{c * v[0] - s * v[1], s * v[0] + c * v[1]}};
}

// ---- evaluation in a kernel ----
template <int D>
struct EvaluateShape {
  ShapeView<D> shape;
  View<const Vec<Real, D>> points;
  View<Real> distance;
  View<int> inside;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    distance[i] = shape.signed_distance(points[i]);
    inside[i] = shape.inside(points[i]) ? 1 : 0;
  }
};

template <int D, class P>
std::vector<Real> evaluate(P policy, CompiledShape<D>& shape, const std::vector<Vec<Real, D>>& points,
                           std::vector<int>* inside = nullptr) {
  DiscreteVariable<Vec<Real, D>> x("ShapeTestPoints");
  x.assign(points);
  DiscreteVariable<Real> d("ShapeTestDistance", points.size());
  DiscreteVariable<int> in("ShapeTestInside", points.size());
  particle_for(policy, points.size(), EvaluateShape<D>{shape.view(policy), x.read(policy), d.write(policy), in.write(policy)});
  if (inside) *inside = in.to_vector();
  return d.to_vector();
}

template <int D>
std::vector<Vec<Real, D>> random_points(Real lo, Real hi, std::size_t count, std::uint64_t seed, bool dyadic = false) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec<Real, D>> points(count);
  for (auto& x : points)
    for (int k = 0; k < D; ++k) {
      x[k] = Real(lo + (hi - lo) * unit(random));
      if (dyadic) x[k] = std::round(x[k] * 64) / 64;
    }
  return points;
}

template <int D>
struct Case {
  const char* name;
  Shape<D> shape;
  Reference<D> reference;
  bool exact;  // every operation exact on dyadic points (sqrt correctly rounded on both sides)
};

template <int D>
std::vector<Case<D>> cases();

template <>
std::vector<Case<2>> cases<2>() {
  const V2 lo{{-0.5, -0.25}}, hi{{0.75, 0.5}}, c{{0.25, -0.125}};
  const Real r = Real(0.625);
  const V2 p{{0.125, 0.25}}, n{{0, 1}}, slanted{{1, -2}};
  auto b = [=](const V2& x) { return box_reference<2>(x, lo, hi); };
  auto s = [=](const V2& x) { return sphere_reference<2>(x, c, r); };
  auto h = [=](const V2& x) { return half_space_reference<2>(x, p, n); };
  auto hs = [=](const V2& x) { return half_space_reference<2>(x, p, slanted); };
  const Shape<2> B = box<2>(lo, hi), S = circle(c, r), H = half_space<2>(p, n), HS = half_space<2>(p, slanted);
  const V2 offset{{0.375, -0.25}}, centre{{0.5, 0.25}};
  const Real angle = Real(0.7);
  return {
      {"box", B, b, true},
      {"circle", S, s, true},
      {"half-space", H, h, true},
      {"slanted half-space", HS, hs, false},
      {"union", union_of(B, S), [=](const V2& x) { return std::min(b(x), s(x)); }, true},
      {"intersection", intersection_of(B, H), [=](const V2& x) { return std::max(b(x), h(x)); }, true},
      {"difference", difference(B, S), [=](const V2& x) { return std::max(b(x), -s(x)); }, true},
      {"shell", shell(S, Real(0.25)), [=](const V2& x) { return std::fabs(s(x)) - Real(0.125); }, true},
      {"complement", complement(B), [=](const V2& x) { return -b(x); }, true},
      {"translated", translate(B, offset), [=](const V2& x) { return b(x - offset); }, true},
      {"scaled", scale(S, Real(2), centre), [=](const V2& x) { return 2 * s((x - centre) / Real(2) + centre); }, true},
      {"rotated", rotate(B, angle, centre), [=](const V2& x) { return b(rotate_back(x, angle, centre)); }, false},
      {"wedge", intersection_of(B, HS), [=](const V2& x) { return std::max(b(x), hs(x)); }, false},
      {"transformed boolean", rotate(scale(difference(B, S), Real(1.5), c), angle, centre),
       [=](const V2& x) {
         const V2 y = (rotate_back(x, angle, centre) - c) / Real(1.5) + c;
         return Real(1.5) * std::max(b(y), -s(y));
       },
       false},
      {"list union", union_of(std::vector<Shape<2>>{B, S, HS}), [=](const V2& x) { return std::min({b(x), s(x), hs(x)}); },
       false},
  };
}

template <>
std::vector<Case<3>> cases<3>() {
  const V3 lo{{-0.5, -0.25, -0.375}}, hi{{0.75, 0.5, 0.25}}, c{{0.25, -0.125, 0.0625}};
  const Real r = Real(0.625);
  const V3 p{{0.125, 0.25, 0}}, n{{0, 0, -1}}, slanted{{1, -2, 0.5}};
  const V3 ca{{-0.3, 0.1, -0.2}}, cb{{0.4, -0.3, 0.5}};
  const Real cr = Real(0.3);
  auto b = [=](const V3& x) { return box_reference<3>(x, lo, hi); };
  auto s = [=](const V3& x) { return sphere_reference<3>(x, c, r); };
  auto h = [=](const V3& x) { return half_space_reference<3>(x, p, n); };
  auto hs = [=](const V3& x) { return half_space_reference<3>(x, p, slanted); };
  auto cy = [=](const V3& x) { return cylinder_reference(x, ca, cb, cr); };
  const Shape<3> B = box<3>(lo, hi), S = sphere<3>(c, r), H = half_space<3>(p, n), HS = half_space<3>(p, slanted),
                 C = cylinder(ca, cb, cr);
  const V3 offset{{0.375, -0.25, 0.125}}, centre{{0.5, 0.25, -0.25}}, axis{{1, 2, -0.5}};
  const Real angle = Real(0.7);
  return {
      {"box", B, b, true},
      {"sphere", S, s, true},
      {"half-space", H, h, true},
      {"slanted half-space", HS, hs, false},
      {"cylinder", C, cy, false},
      {"axis-aligned cylinder", cylinder(V3{{0, 0, -0.5}}, V3{{0, 0, 0.5}}, Real(0.25)),
       [=](const V3& x) { return cylinder_reference(x, V3{{0, 0, -0.5}}, V3{{0, 0, 0.5}}, Real(0.25)); }, false},
      {"union", union_of(B, S), [=](const V3& x) { return std::min(b(x), s(x)); }, true},
      {"intersection", intersection_of(B, H), [=](const V3& x) { return std::max(b(x), h(x)); }, true},
      {"difference", difference(B, S), [=](const V3& x) { return std::max(b(x), -s(x)); }, true},
      {"shell", shell(H, Real(0.25)), [=](const V3& x) { return std::fabs(h(x)) - Real(0.125); }, true},
      {"complement", complement(S), [=](const V3& x) { return -s(x); }, true},
      {"translated", translate(B, offset), [=](const V3& x) { return b(x - offset); }, true},
      {"scaled", scale(B, Real(0.5), centre), [=](const V3& x) { return Real(0.5) * b((x - centre) / Real(0.5) + centre); },
       true},
      {"rotated box", rotate(B, angle, axis, centre), [=](const V3& x) { return b(rotate_back(x, angle, axis, centre)); },
       false},
      {"rotated cylinder", rotate(C, -angle, axis, c), [=](const V3& x) { return cy(rotate_back(x, -angle, axis, c)); },
       false},
      {"transformed boolean", translate(rotate(scale(difference(union_of(B, C), S), Real(1.5), c), angle, axis, centre), offset),
       [=](const V3& x) {
         const V3 y = (rotate_back(x - offset, angle, axis, centre) - c) / Real(1.5) + c;
         return Real(1.5) * std::max(std::min(b(y), cy(y)), -s(y));
       },
       false},
      {"shell of a transformed cylinder", shell(scale(C, Real(2), c), Real(0.1)),
       [=](const V3& x) { return std::fabs(2 * cy((x - c) / Real(2) + c)) - Real(0.05); }, false},
      {"list intersection", intersection_of(std::vector<Shape<3>>{B, S, HS, C}),
       [=](const V3& x) { return std::max({b(x), s(x), hs(x), cy(x)}); }, false},
  };
}

UNISPH_POLICY_TEST_SUITE(ShapeTest);

template <int D, class P>
void check_cases(P policy) {
  for (const Case<D>& c : cases<D>()) {
    SCOPED_TRACE(c.name);
    CompiledShape<D> compiled(c.shape);
    for (const bool dyadic : {true, false}) {
      const auto points = random_points<D>(-2, 2, 3000, dyadic ? 5 : 6, dyadic);
      std::vector<int> inside;
      const std::vector<Real> d = evaluate(policy, compiled, points, &inside);
      Real worst = 0;
      int unequal = 0, wrong_side = 0;
      for (std::size_t i = 0; i < points.size(); ++i) {
        const Real expected = c.reference(points[i]);
        worst = std::max(worst, std::fabs(d[i] - expected));
        unequal += d[i] != expected;
        if (std::fabs(expected) > 4 * roundoff) wrong_side += inside[i] != (expected < 0);
      }
      if (dyadic && c.exact) {
        EXPECT_EQ(unequal, 0) << "worst " << worst;
      }
      EXPECT_LT(worst, 4 * roundoff);
      EXPECT_EQ(wrong_side, 0);
    }
  }
}

TYPED_TEST(ShapeTest, PrimitivesBooleansAndTransformsMatchAnalyticValues2D) { check_cases<2>(this->policy); }
TYPED_TEST(ShapeTest, PrimitivesBooleansAndTransformsMatchAnalyticValues3D) { check_cases<3>(this->policy); }

// The same values on every policy as on seq: bit for bit on the host, to round-off on the GPU
// (which may fuse products into multiply-adds).
TYPED_TEST(ShapeTest, SameValuesAsSeq) {
  for (const Case<3>& c : cases<3>()) {
    SCOPED_TRACE(c.name);
    CompiledShape<3> compiled(c.shape);
    const auto points = random_points<3>(-2, 2, 2000, 9);
    const std::vector<Real> here = evaluate(this->policy, compiled, points), there = evaluate(seq, compiled, points);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if constexpr (TypeParam::space == MemorySpace::host) {
        ASSERT_EQ(here[i], there[i]);
      } else {
        ASSERT_NEAR(here[i], there[i], roundoff);
      }
    }
  }
}

TEST(HostShapeTest, CompiledProgramAndStack) {
  const Shape<3> b = box<3>(V3{{0, 0, 0}}, V3{{1, 1, 1}});
  CompiledShape<3> one(b);
  EXPECT_EQ(one.program_size(), 1u);
  EXPECT_EQ(one.stack_depth(), 1);
  // Balanced list of 64 operands: stack 7 (log2 64 + 1), not 64.
  std::vector<Shape<3>> many;
  for (int i = 0; i < 64; ++i) many.push_back(translate(b, V3{{Real(i), 0, 0}}));
  CompiledShape<3> list(union_of(many));
  EXPECT_EQ(list.program_size(), 127u);
  EXPECT_EQ(list.stack_depth(), 7);
  EXPECT_EQ(list.bounds().lower, (V3{{0, 0, 0}}));
  EXPECT_EQ(list.bounds().upper, (V3{{64, 1, 1}}));
  // Transforms fold into the leaves: no program nodes of their own.
  CompiledShape<3> moved(rotate(translate(b, V3{{1, 0, 0}}), Real(1), V3{{0, 0, 1}}, V3{{0, 0, 0}}));
  EXPECT_EQ(moved.program_size(), 1u);
  EXPECT_FALSE(CompiledShape<3>(half_space<3>(V3{}, V3{{0, 0, 1}})).bounded());
}

// ---- geometry files through the level set ----

Real brute_force_signed_distance(const TriangleMesh& mesh, const V3& point) {
  const Vec<double, 3> p{{point[0], point[1], point[2]}};
  double best = std::numeric_limits<double>::max(), angle = 0;
  for (const auto& t : mesh.triangles) {
    const auto& a = mesh.vertices[t[0]];
    const auto& b = mesh.vertices[t[1]];
    const auto& c = mesh.vertices[t[2]];
    best = std::min(best, squared_distance(p, closest_point_on_triangle(p, a, b, c).point));
    angle += solid_angle(p, a, b, c);
  }
  return Real(angle / (4 * pi<double>()) > 0.5 ? -std::sqrt(best) : std::sqrt(best));
}

// Within two data spacings of the surface (the finest layer's band) a mesh leaf answers the
// level set's trilinear probe of the exact distance: within 0.1 dx of the brute force here
// (smooth parts err by about dx^2 / (8 R); the faceted sphere's edges and the cleaning add
// less than that); the sign is right at every point farther than 0.1 dx from the surface, in or
// beyond the band. Booleans with a mesh combine the probe with the primitive.
TYPED_TEST(ShapeTest, TriangleMeshMatchesBruteForce) {
  const std::string file = test_data("geometry/trimesh_unit_sphere.stl");
  const TriangleMesh mesh = load_triangle_mesh(file).mesh;
  MeshLevelSetCache<3> cache;
  const Real dx = Real(1) / 32;
  const Shape<3> ball = triangle_mesh(this->policy, cache, file, dx);
  const Shape<3> same = triangle_mesh(this->policy, cache, file, dx);  // from the cache
  EXPECT_EQ(cache.size(), 1u);
  const V3 lo = cache.get(this->policy, file, dx)->lower(), hi = cache.get(this->policy, file, dx)->upper();
  const V3 centre = (lo + hi) * Real(0.5);
  const Real radius = (hi[0] - lo[0]) / 2;
  const V3 cut{{0.125, 0, 0}};
  CompiledShape<3> compiled(ball);
  CompiledShape<3> boolean(difference(same, translate(box<3>(centre, hi + V3::constant(1)), cut)));
  EXPECT_EQ(boolean.geometry_files(), 1u);
  const std::vector<V3> points = random_points<3>(-1.5 * radius, 1.5 * radius, 1500, 3);
  std::vector<V3> shifted;
  for (const V3& x : points) shifted.push_back(x + centre);
  const std::vector<Real> d = evaluate(this->policy, compiled, shifted), e = evaluate(this->policy, boolean, shifted);
  Real worst = 0;
  int in_band = 0, wrong_sign = 0, wrong_boolean = 0;
  for (std::size_t i = 0; i < shifted.size(); ++i) {
    const Real exact = brute_force_signed_distance(mesh, shifted[i]);
    if (std::fabs(exact) < 2 * dx) {
      ++in_band;
      worst = std::max(worst, std::fabs(d[i] - exact));
    }
    if (std::fabs(exact) > dx / 10) wrong_sign += (d[i] < 0) != (exact < 0);
    const Real box_part = box_reference<3>(shifted[i], centre + cut, hi + V3::constant(1) + cut);
    const Real combined = std::max(exact, -box_part);
    if (std::fabs(combined) > dx / 10) wrong_boolean += (e[i] < 0) != (combined < 0);
  }
  std::printf("unit sphere mesh at dx = 1/32: %d points within 2 dx, worst |phi - brute force| %.3g dx\n", in_band,
              double(worst / dx));
  EXPECT_GT(in_band, 50);
  EXPECT_LT(worst, dx / 10);
  EXPECT_EQ(wrong_sign, 0);
  EXPECT_EQ(wrong_boolean, 0);
  // The same values as seq.
  const std::vector<Real> reference = evaluate(seq, compiled, shifted);
  for (std::size_t i = 0; i < shifted.size(); ++i) ASSERT_NEAR(d[i], reference[i], roundoff);
}

TYPED_TEST(ShapeTest, PolygonMatchesBruteForce) {
  const std::string file = test_data("geometry/plate_with_holes.poly");
  const PolygonSet polygons = read_polygons(file).polygons;
  MeshLevelSetCache<2> cache;
  const Real dx = Real(0.05);
  CompiledShape<2> plate(polygon(this->policy, cache, file, dx));
  const V2 lo = plate.bounds().lower, hi = plate.bounds().upper;
  std::vector<V2> points = random_points<2>(0, 1, 4000, 8);
  for (V2& x : points)
    for (int k = 0; k < 2; ++k) x[k] = lo[k] - 1 + x[k] * (hi[k] - lo[k] + 2);
  const std::vector<Real> d = evaluate(this->policy, plate, points);
  Real worst = 0, worst_away = 0;
  int in_band = 0, wrong_sign = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    double best = std::numeric_limits<double>::max();
    bool inside = false;
    const Vec<double, 2> p{{points[i][0], points[i][1]}};
    for (std::size_t loop = 0; loop + 1 < polygons.loop_start.size(); ++loop) {
      const std::uint32_t begin = polygons.loop_start[loop], end = polygons.loop_start[loop + 1];
      for (std::uint32_t j = begin; j < end; ++j) {
        const Vec<double, 2> a = polygons.vertices[j], c = polygons.vertices[j + 1 < end ? j + 1 : begin];
        const Vec<double, 2> e = c - a;
        const double t = std::clamp(dot(p - a, e) / dot(e, e), 0.0, 1.0);
        best = std::min(best, squared_norm(p - (a + e * t)));
        if ((a[1] > p[1]) != (c[1] > p[1]) && p[0] < a[0] + (p[1] - a[1]) / (c[1] - a[1]) * e[0]) inside = !inside;
      }
    }
    const Real exact = Real(inside ? -std::sqrt(best) : std::sqrt(best));
    double corner = std::numeric_limits<double>::max();
    for (const auto& v : polygons.vertices) corner = std::min(corner, norm(p - v));
    if (std::fabs(exact) < 2 * dx) {
      ++in_band;
      worst = std::max(worst, std::fabs(d[i] - exact));
      if (corner > 10 * dx) worst_away = std::max(worst_away, std::fabs(d[i] - exact));
    }
    if (std::fabs(exact) > dx / 10) wrong_sign += (d[i] < 0) != (exact < 0);
  }
  std::printf("plate_with_holes.poly at dx = %.3g: %d points within 2 dx, worst |phi - brute force| %.3g dx, %.3g dx "
              "farther than 10 dx from every corner\n",
              double(dx), in_band, double(worst / dx), double(worst_away / dx));
  EXPECT_GT(in_band, 100);
  // Next to corners the stencil straddles a ridge of the distance (the medial axis).
  EXPECT_LT(worst, dx / 4);
  EXPECT_LT(worst_away, roundoff * 100);
  EXPECT_EQ(wrong_sign, 0);
}

// ---- particles on the lattice ----

template <int D>
bool less(const Vec<Real, D>& a, const Vec<Real, D>& b) {
  for (int k = D - 1; k >= 0; --k)
    if (a[k] != b[k]) return a[k] < b[k];
  return false;
}

template <int D, class P>
void check_fill_against_tank(P policy) {
  const double dx = 0.02;
  const std::vector<double> tank = {1.6, 0.8, 0.6};
  for (const std::vector<double>& column : {std::vector<double>{0.6, 0.4, 0.3}, std::vector<double>{0.37, 0.253, 0.111}}) {
    const auto expected = sph::make_tank_particles<Real, D>(tank, column, dx);
    Vec<Real, D> upper;
    for (int k = 0; k < D; ++k) upper[k] = Real(column[k]);
    CompiledShape<D> water(box<D>(Vec<Real, D>{}, upper));
    const std::vector<Vec<Real, D>> fluid = fill_with_particles(policy, water, Real(dx));
    ASSERT_EQ(fluid.size(), expected.fluid.size());
    // Bit for bit in double; with unisph::Real = float (UNISPH_SINGLE_PRECISION) the lattice's
    // origin + (i + 1/2) dx and the tank's (i + 1/2) dx round differently in the last bit.
    for (std::size_t i = 0; i < fluid.size(); ++i)
      for (int k = 0; k < D; ++k) {
        if (sizeof(Real) == 8) ASSERT_EQ(fluid[i][k], expected.fluid[i][k]) << i;
        else ASSERT_NEAR(fluid[i][k], expected.fluid[i][k], 1e-6) << i;
      }
  }
}
TYPED_TEST(ShapeTest, BoxFillGivesTheTankFluidBitForBit) {
  check_fill_against_tank<2>(this->policy);
  check_fill_against_tank<3>(this->policy);
}

// difference(outer, inner) gives the tank's wall positions; its normals agree with the tank's
// where the inner surface is the nearer one (the two layers next to the fluid, and the corners
// up to the diagonal), and point out of the tank on the outer layers (outside the kernel's
// reach of the fluid at h = 1.3 dx). complement(inner) over the same region gives positions
// and normals both.
template <int D, class P>
void check_walls_against_tank(P policy) {
  const double dx = 0.025;
  const std::vector<double> tank = {1.0, 0.5, 0.75}, column = {0.5, 0.25, 0.25};
  const auto expected = sph::make_tank_particles<Real, D>(tank, column, dx);
  Vec<Real, D> upper;
  for (int k = 0; k < D; ++k) upper[k] = Real(tank[k]);
  const Real layers = Real(4 * dx);
  const Shape<D> inner = box<D>(Vec<Real, D>{}, upper);
  const Shape<D> hollow = difference(box<D>(Vec<Real, D>::constant(-layers), upper + Vec<Real, D>::constant(layers)), inner);
  CompiledShape<D> difference_walls(hollow), complement_walls(complement(inner));
  const LatticeParticles<D> a = make_wall_particles(policy, difference_walls, Real(dx));
  // The complement's depth is the distance to the inner box: the tank's square corners reach
  // 3.5 sqrt(D) dx deep, so the layers are counted to 7 and the region clips them to the tank's.
  LatticeOptions<D> region;
  region.region = Box<Real, D>{Vec<Real, D>::constant(-layers), upper + Vec<Real, D>::constant(layers)};
  const LatticeParticles<D> four = make_wall_particles(policy, complement_walls, Real(dx), 4, region);
  const LatticeParticles<D> b = make_wall_particles(policy, complement_walls, Real(dx), 7, region);
  EXPECT_LT(four.position.size(), expected.wall.size());
  ASSERT_EQ(a.position.size(), expected.wall.size());
  ASSERT_EQ(b.position.size(), expected.wall.size());
  int reversed = 0;
  for (std::size_t i = 0; i < expected.wall.size(); ++i) {
    // Same lattice order as make_tank_particles (x fastest).
    ASSERT_LT(norm(a.position[i] - expected.wall[i]), 4 * roundoff) << i;
    ASSERT_LT(norm(b.position[i] - expected.wall[i]), 4 * roundoff) << i;
    // The tank's normal points into the fluid, i.e. out of the solid.
    ASSERT_LT(norm(b.normal[i] - expected.wall_normal[i]), single ? Real(2e-3) : Real(1e-4)) << i;
    const Real inner_distance = box_reference<D>(expected.wall[i], Vec<Real, D>{}, upper);
    const Real outer_distance =
        -box_reference<D>(expected.wall[i], Vec<Real, D>::constant(-layers), upper + Vec<Real, D>::constant(layers));
    if (inner_distance < outer_distance - Real(dx) / 4)
      ASSERT_LT(norm(a.normal[i] - expected.wall_normal[i]), single ? Real(2e-3) : Real(1e-4)) << i;
    else if (dot(a.normal[i], expected.wall_normal[i]) < 0)
      ++reversed;
  }
  std::printf("%dD tank: %zu wall particles; difference(outer, inner): %d normals point out of the tank (outer layers)\n",
              D, expected.wall.size(), reversed);
  EXPECT_GT(reversed, 0);
}
TYPED_TEST(ShapeTest, HollowTankWallsMatchTheTank) {
  check_walls_against_tank<2>(this->policy);
  check_walls_against_tank<3>(this->policy);
}

// Wall layers of a rotated box and a sphere against a brute-force loop over the lattice.
TYPED_TEST(ShapeTest, WallLayersMatchBruteForce) {
  const Real dx = Real(0.05);
  const V3 c{{0.013, -0.021, 0.034}};
  const Real r = Real(0.61);
  CompiledShape<3> ball(sphere<3>(c, r));
  const LatticeParticles<3> wall = make_wall_particles(this->policy, ball, dx, 3);
  std::vector<V3> expected;
  int ambiguous = 0;
  for (int k = -20; k < 20; ++k)
    for (int j = -20; j < 20; ++j)
      for (int i = -20; i < 20; ++i) {
        const V3 x{{(Real(i) + Real(0.5)) * dx, (Real(j) + Real(0.5)) * dx, (Real(k) + Real(0.5)) * dx}};
        const Real d = sphere_reference<3>(x, c, r);
        if (std::fabs(d) < roundoff || std::fabs(d + 3 * dx) < roundoff) ++ambiguous;
        if (d < 0 && d > -3 * dx) expected.push_back(x);
      }
  EXPECT_EQ(ambiguous, 0);
  ASSERT_EQ(wall.position.size(), expected.size());
  Real worst_normal = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    ASSERT_EQ(wall.position[i], expected[i]);
    worst_normal = std::max(worst_normal, norm(wall.normal[i] - (expected[i] - c) / norm(expected[i] - c)));
  }
  EXPECT_LT(worst_normal, single ? Real(1e-3) : Real(1e-5));

  // A rotated box: the fill against the lattice points whose cell centre lies dx/2 deep.
  const V3 lo{{-0.4, -0.3, -0.2}}, hi{{0.45, 0.3, 0.25}}, axis{{1, 1, 0}}, centre{{0.1, 0, 0}};
  const Real angle = Real(0.4);
  CompiledShape<3> turned(rotate(box<3>(lo, hi), angle, axis, centre));
  const std::vector<V3> fill = fill_with_particles(this->policy, turned, dx);
  const std::vector<V3> fill_centres = fill_with_particles(this->policy, turned, dx, FillRule::centre_inside);
  std::size_t deep = 0, inside = 0;
  for (int k = -20; k < 20; ++k)
    for (int j = -20; j < 20; ++j)
      for (int i = -20; i < 20; ++i) {
        const V3 x{{(Real(i) + Real(0.5)) * dx, (Real(j) + Real(0.5)) * dx, (Real(k) + Real(0.5)) * dx}};
        const Real d = box_reference<3>(rotate_back(x, angle, axis, centre), lo, hi);
        deep += d < -dx / 2;
        inside += d < 0;
      }
  EXPECT_EQ(fill.size(), deep);
  EXPECT_EQ(fill_centres.size(), inside);
  EXPECT_TRUE(std::is_sorted(fill.begin(), fill.end(), less<3>));
}

TYPED_TEST(ShapeTest, FluidNearAWallIsRemoved) {
  const Real dx = Real(0.02);
  CompiledShape<2> water(box<2>(V2{{0, 0}}, V2{{1, 0.6}}));
  CompiledShape<2> obstacle(union_of(circle(V2{{0.5, 0.2}}, Real(0.137)), box<2>(V2{{0.8, -1}}, V2{{0.9, 0.3}})));
  std::vector<V2> fluid = fill_with_particles(this->policy, water, dx);
  const std::vector<V2> before = fluid;
  const Index removed = remove_near_wall(this->policy, fluid, obstacle, dx);
  std::vector<V2> expected;
  for (const V2& x : before) {
    const Real d = std::min(sphere_reference<2>(x, V2{{0.5, 0.2}}, Real(0.137)),
                            box_reference<2>(x, V2{{0.8, -1}}, V2{{0.9, 0.3}}));
    if (d >= dx / 2 * (1 - Real(1e-6))) expected.push_back(x);
  }
  EXPECT_EQ(fluid, expected);
  EXPECT_EQ(removed, before.size() - expected.size());
  // The box's sides lie on cell faces: the points dx/2 from them stay.
  EXPECT_GT(removed, 0u);
  std::printf("removed %zu of %zu fluid points next to the obstacle\n", std::size_t(removed), before.size());
}

// The example of docs/shapes.md: the 3D dam break of cases/dambreak_obstacle_3d.toml from shapes.
TYPED_TEST(ShapeTest, DocumentedExample) {
  const auto policy = this->policy;
  const Real dx = Real(0.05);
  const V3 inside{{5.366, 2.0, 0.5}};
  const V3 layers = V3::constant(4 * dx);
  MeshLevelSetCache<3> cache;

  const Shape<3> tank = difference(box<3>(-layers, inside + layers), box<3>(V3{}, inside));
  const Shape<3> water = box<3>(V3{}, V3{{2.0, 1.0, 0.5}});
  const Shape<3> pillar = translate(triangle_mesh(policy, cache, test_data("../../cases/obstacle_3d.stl"), dx / 2),
                                    V3{{3.5, 0.0, 0.15}});

  CompiledShape<3> tank_solid(tank), water_region(water), pillar_solid(pillar);
  std::vector<V3> fluid = fill_with_particles(policy, water_region, dx);
  const Index removed = remove_near_wall(policy, fluid, pillar_solid, dx);
  const LatticeParticles<3> tank_wall = make_wall_particles(policy, tank_solid, dx);
  const LatticeParticles<3> pillar_wall = make_wall_particles(policy, pillar_solid, dx);

  std::printf("fluid %zu (removed %zu), tank wall %zu, pillar wall %zu\n", fluid.size(), std::size_t(removed),
              tank_wall.position.size(), pillar_wall.position.size());
  EXPECT_EQ(fluid.size(), 40u * 20u * 10u);
  EXPECT_EQ(removed, 0u);  // the water column does not reach the pillar
  // The pillar (0.3 x 0.8 x 0.2 at dx 0.05) is 6 x 16 x 4 cells: every cell centre is less than
  // 4 dx deep, so all of them are wall particles.
  EXPECT_EQ(pillar_wall.position.size(), 6u * 16u * 4u);
  for (const V3& n : pillar_wall.normal) ASSERT_NEAR(norm(n), 1, 1e-6);
}

// ---- bad input: one line each, a unisph::Error ----

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(HostShapeTest, BadInputThrowsOneClearLine) {
  MeshLevelSetCache<3> cache;
  MeshLevelSetCache<2> cache2;
  const Shape<3> b = box<3>(V3{}, V3::constant(1));
  std::vector<Shape<3>> deep_chain{b};
  Shape<3> deep = b;
  for (int i = 0; i < 20; ++i) deep = difference(b, deep);  // right operands nest: stack 21
  const std::vector<std::pair<std::string, std::function<void()>>> cases = {
      {"cannot open the file", [&] { triangle_mesh(seq, cache, "no_such_file.stl", Real(0.1)); }},
      {"cannot open the file", [&] { polygon(seq, cache2, "no_such_file.poly", Real(0.1)); }},
      {"resolution must be positive", [&] { triangle_mesh(seq, cache, test_data("geometry/trimesh_unit_sphere.stl"), 0); }},
      {"union of nothing", [&] { union_of(std::vector<Shape<3>>{}); }},
      {"intersection of nothing", [&] { intersection_of(std::vector<Shape<2>>{}); }},
      {"of an empty shape", [&] { difference(b, Shape<3>{}); }},
      {"of an empty shape", [&] { translate(Shape<3>{}, V3{}); }},
      {"cannot compile an empty shape", [&] { CompiledShape<3>{Shape<3>{}}; }},
      {"two different finite axis points", [&] { cylinder(V3::constant(1), V3::constant(1), 1); }},
      {"positive radius", [&] { cylinder(V3{}, V3::constant(1), 0); }},
      {"positive radius", [&] { sphere<3>(V3{}, -1); }},
      {"positive radius", [&] { circle(V2{}, 0); }},
      {"positive factor", [&] { scale(b, 0); }},
      {"positive factor", [&] { scale(b, -2); }},
      {"positive thickness", [&] { shell(b, 0); }},
      {"lower < upper", [&] { box<3>(V3::constant(1), V3::constant(1)); }},
      {"non-zero normal", [&] { half_space<3>(V3{}, V3{}); }},
      {"non-zero axis", [&] { rotate(b, 1, V3{}, V3{}); }},
      {"evaluation stack of 21 entries", [&] { CompiledShape<3>{deep}; }},
      {"region is unbounded", [&] {
         CompiledShape<3> open(half_space<3>(V3{}, V3{{0, 0, 1}}));
         fill_with_particles(seq, open, Real(0.1));
       }},
      {"lattice spacing must be positive", [&] {
         CompiledShape<3> closed(b);
         fill_with_particles(seq, closed, Real(0));
       }},
      {"at least one layer", [&] {
         CompiledShape<3> closed(b);
         make_wall_particles(seq, closed, Real(0.1), 0);
       }},
  };
  for (const auto& [phrase, f] : cases) {
    const std::string message = error_of(f);
    EXPECT_NE(message.find(phrase), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    std::printf("  %s\n", message.c_str());
  }
  EXPECT_EQ(cache.size(), 0u);  // nothing cached from a failed build
}

}  // namespace
