// Measurements and wave absorption (issue 22; docs/motion.md, "Measurements and wave
// absorption"), on water lattices built by hand (particles at the cell centres of a box, at rest
// density, mass rho0 dx^D), with a cell list and an inner relation as the solver builds them, on
// every policy:
//  * wave gauges (sph/wave_gauge.hpp): a flat surface of depth d read within 0.1 dx in 2D and
//    3D, a surface sloping at 0.2 within 0.5 dx of the local height, dry and submerged lines,
//    the same readings with the particles in cell order; the crossing search on its own (host);
//  * velocity probes (sph/velocity_probe.hpp): a uniform field exactly, a linear field exactly
//    (to round-off) at the points of lattice symmetry and within the lattice's first moment
//    elsewhere (|x_bar - x| <= 0.0068 dx), a dry probe;
//  * the damping zone (sph/damping_zone.hpp): a uniform field decays by the zone's factor exactly
//    inside, bit for bit untouched outside, at the documented rate; the neighbour records follow;
//    the zone length against the dispersion relation, the group velocity, the strength estimate
//    (host).
// Each measured figure is printed beside its bound ("[ measured ]").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/motion/linear_waves.hpp"
#include "unisph/neighbor/cell_linked_list.hpp"
#include "unisph/neighbor/inner_relation.hpp"
#include "unisph/neighbor/particle_sorter.hpp"
#include "unisph/sph/damping_zone.hpp"
#include "unisph/sph/neighbor_records.hpp"
#include "unisph/sph/velocity_probe.hpp"
#include "unisph/sph/wave_gauge.hpp"

using namespace unisph;
using namespace unisph::sph;

namespace {

constexpr double rho0 = 1000.0;
constexpr double g = 9.81;

template <int D>
using V = Vec<double, D>;

// The cell centres of a lattice of spacing dx over [0, n[0] dx] x [0, n[1] dx] (x [0, n[2] dx])
// where keep(x) holds, axis 0 fastest (not in cell order).
template <int D>
std::vector<V<D>> lattice(const std::array<int, D>& n, double dx, const std::function<bool(const V<D>&)>& keep) {
  std::vector<V<D>> points;
  std::array<int, 3> m{n[0], n[1], D == 3 ? n[D - 1] : 1};
  for (int c = 0; c < m[2]; ++c)
    for (int b = 0; b < m[1]; ++b)
      for (int a = 0; a < m[0]; ++a) {
        V<D> x{};
        x[0] = (a + 0.5) * dx;
        x[1] = (b + 0.5) * dx;
        if constexpr (D == 3) x[2] = (c + 0.5) * dx;
        if (keep(x)) points.push_back(x);
      }
  return points;
}

// A fluid body built by hand: the points at rest density, zero velocity and pressure, the
// neighbour records written; its cell list (cells of the cutoff) and inner relation over `box`.
template <int D>
struct Water {
  double dx;
  Body<double, D> body;
  FluidVariables<double, D> fluid;
  WendlandC2Kernel<double, D> kernel;
  CellLinkedList<double, D> cells;
  InnerRelation<double, D> inner;

  Water(const std::vector<V<D>>& points, double spacing, const Box<double, D>& box)
      : dx(spacing),
        body("Water", box, points.size()),
        fluid(body),
        kernel(WendlandC2Kernel<double, D>::from_spacing(spacing)),
        cells(body.positions(), box, kernel.cutoff()),
        inner(cells) {
    double volume = 1;
    for (int a = 0; a < D; ++a) volume *= dx;
    View<V<D>> x = fluid.position.write(MemorySpace::host);
    View<V<D>> v = fluid.velocity.write(MemorySpace::host);
    View<double> rho = fluid.density.write(MemorySpace::host);
    View<double> p = fluid.pressure.write(MemorySpace::host);
    View<double> m = fluid.mass.write(MemorySpace::host);
    for (Index i = 0; i < points.size(); ++i) {
      x[i] = points[i];
      v[i] = V<D>{};
      rho[i] = rho0;
      p[i] = 0;
      m[i] = rho0 * volume;
    }
  }
  template <class P>
  void build(P policy) {
    RefreshNeighborRecords<double, D>(fluid).exec(policy);
    cells.build(policy);
    inner.update(policy);
  }
  // Sorts the particles by cell (as the solver does) and rebuilds: the search then walks cells as
  // contiguous index ranges.
  template <class P>
  void sort_and_build(P policy) {
    ParticleSorter<double, D> sorter(body.particles(), fluid.position, cells.grid(), 1, SortOrder::cell_index);
    sorter.sort(policy);
    build(policy);
  }
};

template <int D>
Box<double, D> box_of(V<D> lower, V<D> upper) {
  return Box<double, D>{lower, upper};
}

template <int D>
V<D> vec(std::initializer_list<double> values) {
  V<D> v{};
  int a = 0;
  for (double x : values) v[a++] = x;
  return v;
}

// "<prefix><k>" (through snprintf: GCC 12 warns falsely on "p" + std::to_string(k), -Wrestrict).
std::string numbered(const char* prefix, int k) {
  char name[32];
  std::snprintf(name, sizeof name, "%s%d", prefix, k);
  return name;
}

double largest(const std::vector<double>& values) {
  double m = 0;
  for (double v : values) m = std::max(m, std::abs(v));
  return m;
}

}  // namespace

UNISPH_POLICY_TEST_SUITE(Measurements);

// ---------------------------------------------------------------------------------------------
// Wave gauges

// Water of depth d = 20 dx over 60 dx, read by gauges on a column of particles, half-way between
// two columns and at a generic place, from below the floor, from the floor and from mid-depth.
TYPED_TEST(Measurements, GaugesReadAFlatSurfaceWithinATenthOfDx) {
  const double dx = 0.05, depth = 20 * dx, width = 60 * dx;
  Water<2> water(lattice<2>({60, 20}, dx, [](const V<2>&) { return true; }), dx,
                 box_of<2>(vec<2>({-4 * dx, -4 * dx}), vec<2>({width + 4 * dx, depth + 8 * dx})));
  water.build(this->policy);
  const double column = 30.5 * dx, between = 30 * dx, generic = 27.3 * dx;
  std::vector<WaveGaugeLine<double, 2>> lines{
      {"column", vec<2>({column, 0.0}), -3 * dx, depth + 6 * dx},
      {"between", vec<2>({between, 0.0}), -3 * dx, depth + 6 * dx},
      {"generic", vec<2>({generic, 0.0}), 0.0, depth + 6 * dx},
      {"mid_depth", vec<2>({column, 7.0}), 0.5 * depth, depth + 3.3 * dx},  // only x counts
      {"coarse", vec<2>({generic, 0.0}), 0.0, depth + 6 * dx},
  };
  WaveGauges<double, 2> gauges(water.fluid, water.cells, water.kernel, dx, vec<2>({0.0, -g}), lines);
  WaveGauges<double, 2> coarse(water.fluid, water.cells, water.kernel, dx, vec<2>({0.0, -g}),
                               {lines[4]}, 0.5);  // samples dx/2 apart
  std::vector<GaugeReading<double>> r = gauges.measure(this->policy);
  r.push_back(coarse.measure(this->policy)[0]);
  ASSERT_EQ(r.size(), 6u);
  std::vector<double> error;
  for (std::size_t k = 0; k < r.size(); ++k) {
    EXPECT_EQ(r[k].state, GaugeState::wet) << k;
    error.push_back((r[k].elevation - depth) / dx);
  }
  const double worst = largest(error);
  std::printf("[ measured ] flat surface, 2D, d = 20 dx: elevation - d = %.5f (column), %.5f (between columns), "
              "%.5f (generic), %.5f (from mid-depth), %.5f (dx/2 samples) dx; bound 0.1 dx\n",
              error[0], error[1], error[2], error[3], error[5]);
  EXPECT_LT(worst, 0.1);
  // The samples' levels run from bottom to top, the top exactly, at most dx/4 apart.
  const std::vector<double> levels = gauges.levels(3);
  EXPECT_EQ(levels.front(), 0.5 * depth);
  EXPECT_EQ(levels.back(), depth + 3.3 * dx);
  for (std::size_t k = 1; k < levels.size(); ++k) EXPECT_LE(levels[k] - levels[k - 1], 0.25 * dx * (1 + 1e-12));
  // Inside the water the sum is about 1, below the floor 0, at the floor about 1/2.
  const std::vector<double> sums = gauges.kernel_sums(0);
  EXPECT_EQ(sums.front(), 0.0);
  EXPECT_NEAR(sums[sums.size() / 2], 1.0, 0.02);
  const std::vector<std::string> names = gauges.column_names();
  ASSERT_EQ(names.size(), 5u);
  EXPECT_EQ(names[0], "gauge_column");
  EXPECT_EQ(names[4], "gauge_coarse");

  // The same water in cell order (the direct search's contiguous path): the same readings to
  // round-off (the sums add the same particles in another order).
  EXPECT_FALSE(water.cells.report().in_cell_order);
  water.sort_and_build(this->policy);
  EXPECT_TRUE(water.cells.report().in_cell_order);
  const std::vector<GaugeReading<double>> sorted = gauges.measure(this->policy);
  for (std::size_t k = 0; k < sorted.size(); ++k) {
    EXPECT_EQ(sorted[k].state, GaugeState::wet);
    EXPECT_NEAR(sorted[k].elevation, r[k].elevation, 1e-12) << k;
  }
}

// The free surface y = d0 + s (x - xc), s = 0.2: the lattice cut by that line. Gauges read the
// local height d0 + s (x - xc).
TYPED_TEST(Measurements, GaugesReadASlopingSurfaceWithinHalfDx) {
  const double dx = 0.05, d0 = 1.0, slope = 0.2, width = 80 * dx, xc = 0.5 * width;
  const auto surface = [&](double x) { return d0 + slope * (x - xc); };
  Water<2> water(lattice<2>({80, 40}, dx, [&](const V<2>& x) { return x[1] < surface(x[0]); }), dx,
                 box_of<2>(vec<2>({-4 * dx, -4 * dx}), vec<2>({width + 4 * dx, 2.0})));
  water.build(this->policy);
  std::vector<WaveGaugeLine<double, 2>> lines;
  std::vector<double> xs;
  for (int k = 0; k < 9; ++k) {
    const double x = xc + (k - 4) * 3.37 * dx;
    xs.push_back(x);
    lines.push_back({numbered("g", k), vec<2>({x, 0.0}), 0.0, 1.9});
  }
  WaveGauges<double, 2> gauges(water.fluid, water.cells, water.kernel, dx, vec<2>({0.0, -g}), lines);
  const std::vector<GaugeReading<double>> r = gauges.measure(this->policy);
  std::vector<double> error;
  for (std::size_t k = 0; k < r.size(); ++k) {
    EXPECT_EQ(r[k].state, GaugeState::wet);
    error.push_back((r[k].elevation - surface(xs[k])) / dx);
  }
  double mean = 0;
  for (double e : error) mean += e / double(error.size());
  std::printf("[ measured ] sloping surface (slope 0.2), 2D: largest |elevation - local height| = %.4f dx, mean "
              "%.4f dx over 9 gauges; bound 0.5 dx\n",
              largest(error), mean);
  EXPECT_LT(largest(error), 0.5);
}

// A line with no water on it reads its bottom (dry); a line below the surface reads its top
// (submerged); a line whose bottom is in the water and top in the air reads the surface.
TYPED_TEST(Measurements, GaugesTellDryAndSubmergedLines) {
  const double dx = 0.1, depth = 10 * dx, width = 30 * dx;
  Water<2> water(lattice<2>({30, 10}, dx, [](const V<2>&) { return true; }), dx,
                 box_of<2>(vec<2>({-4 * dx, -4 * dx}), vec<2>({width + 20 * dx, 2.0})));
  water.build(this->policy);
  WaveGauges<double, 2> gauges(water.fluid, water.cells, water.kernel, dx, vec<2>({0.0, -g}),
                               {{"dry", vec<2>({width + 10 * dx, 0.0}), 0.0, 1.5},
                                {"submerged", vec<2>({15 * dx, 0.0}), 0.1, 0.6},
                                {"wet", vec<2>({15 * dx, 0.0}), 0.6, 1.5}});
  const std::vector<GaugeReading<double>> r = gauges.measure(this->policy);
  EXPECT_EQ(r[0].state, GaugeState::dry);
  EXPECT_EQ(r[0].elevation, 0.0);
  EXPECT_EQ(r[1].state, GaugeState::submerged);
  EXPECT_EQ(r[1].elevation, 0.6);
  EXPECT_EQ(r[2].state, GaugeState::wet);
  EXPECT_NEAR(r[2].elevation, depth, 0.1 * dx);
  EXPECT_STREQ(to_string(r[0].state), "dry");
  EXPECT_STREQ(to_string(r[1].state), "submerged");
  // No gauge: nothing measured, nothing launched.
  WaveGauges<double, 2> none(water.fluid, water.cells, water.kernel, dx, vec<2>({0.0, -g}), {});
  EXPECT_TRUE(none.measure(this->policy).empty());
}

// 3D, gravity along -y: water of depth 12 dx in a 16 x 16 dx box; gauges at (x, z).
TYPED_TEST(Measurements, GaugesReadAFlatSurfaceIn3D) {
  const double dx = 0.1, depth = 12 * dx, width = 16 * dx;
  Water<3> water(lattice<3>({16, 12, 16}, dx, [](const V<3>&) { return true; }), dx,
                 box_of<3>(vec<3>({-4 * dx, -4 * dx, -4 * dx}), vec<3>({width + 4 * dx, 2.0, width + 4 * dx})));
  water.build(this->policy);
  WaveGauges<double, 3> gauges(water.fluid, water.cells, water.kernel, dx, vec<3>({0.0, -g, 0.0}),
                               {{"site", vec<3>({8.5 * dx, 0.0, 8.5 * dx}), 0.0, 1.8},
                                {"corner", vec<3>({8 * dx, 0.0, 8 * dx}), 0.0, 1.8},
                                {"generic", vec<3>({7.3 * dx, 0.0, 8.8 * dx}), 0.0, 1.8}});
  const std::vector<GaugeReading<double>> r = gauges.measure(this->policy);
  std::vector<double> error;
  for (const GaugeReading<double>& reading : r) {
    EXPECT_EQ(reading.state, GaugeState::wet);
    error.push_back((reading.elevation - depth) / dx);
  }
  std::printf("[ measured ] flat surface, 3D, d = 12 dx: elevation - d = %.5f (on a column), %.5f (between four "
              "columns), %.5f (generic) dx; bound 0.1 dx\n",
              error[0], error[1], error[2]);
  EXPECT_LT(largest(error), 0.1);
}

// The crossing search on given sums (host): the highest crossing, interpolated; dry; submerged.
TEST(HostMeasurements, HighestCrossingOfTheKernelSum) {
  const double levels[5] = {0, 1, 2, 3, 4};
  const double two_crossings[5] = {0.25, 0.75, 0.75, 0.25, 0.0};  // rises above the floor, falls at the surface
  GaugeReading<double> r = highest_crossing(levels, two_crossings, 5, 0.5);
  EXPECT_EQ(r.state, GaugeState::wet);
  EXPECT_EQ(r.elevation, 2.5);
  const double exactly_at_threshold[5] = {1, 1, 0.5, 0.25, 0};  // >= counts as inside
  EXPECT_EQ(highest_crossing(levels, exactly_at_threshold, 5, 0.5).elevation, 2.0);
  const double dry[5] = {0.4, 0.3, 0.2, 0.1, 0};
  r = highest_crossing(levels, dry, 5, 0.5);
  EXPECT_EQ(r.state, GaugeState::dry);
  EXPECT_EQ(r.elevation, 0.0);
  const double submerged[5] = {1, 1, 1, 1, 0.5};
  r = highest_crossing(levels, submerged, 5, 0.5);
  EXPECT_EQ(r.state, GaugeState::submerged);
  EXPECT_EQ(r.elevation, 4.0);
  const double nan_above[5] = {1, 1, std::numeric_limits<double>::quiet_NaN(), 0, 0};
  EXPECT_TRUE(std::isnan(highest_crossing(levels, nan_above, 5, 0.5).elevation));
}

TEST(HostMeasurements, BadGaugesAndProbesAreOneLineErrors) {
  const double dx = 0.1;
  Water<2> water(lattice<2>({4, 4}, dx, [](const V<2>&) { return true; }), dx,
                 box_of<2>(vec<2>({0.0, 0.0}), vec<2>({1.0, 1.0})));
  const V<2> down = vec<2>({0.0, -g});
  const auto message = [&](std::vector<WaveGaugeLine<double, 2>> lines, V<2> gravity = vec<2>({0.0, -g}),
                           double spacing = 0.25) {
    try {
      WaveGauges<double, 2> gauges(water.fluid, water.cells, water.kernel, dx, gravity, std::move(lines), spacing);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({{"a", vec<2>({0.5, 0.0}), 1.0, 1.0}}),
            "wave gauge 0 'a': the top (1.000000) must be above the bottom (1.000000), both finite");
  EXPECT_EQ(message({{"a", vec<2>({0.5, 0.0}), 0.0, 1.0}, {"a", vec<2>({0.6, 0.0}), 0.0, 1.0}}),
            "wave gauge 1 'a': the name is taken by gauge 0");
  EXPECT_EQ(message({{"a b", vec<2>({0.5, 0.0}), 0.0, 1.0}}),
            "wave gauge 0 'a b': the name may hold letters, digits, '_', '-' and '.' only (it names a CSV column)");
  EXPECT_EQ(message({{"", vec<2>({0.5, 0.0}), 0.0, 1.0}}), "wave gauge 0: the name is empty");
  EXPECT_EQ(message({{"a", vec<2>({std::nan(""), 0.0}), 0.0, 1.0}}), "wave gauge 0 'a': the position must be finite");
  EXPECT_EQ(message({}, vec<2>({0.0, 0.0})),
            "wave gauges: gravity must be finite and not zero; it gives the gauges' vertical");
  EXPECT_EQ(message({}, down, 0.6), "wave gauges: the sample spacing must be in (0, 0.5] dx (it is 0.600000 dx)");
  try {
    VelocityProbes<double, 2> probes(water.fluid, water.cells, water.kernel,
                                     {{"u", vec<2>({0.5, 0.5})}, {"u", vec<2>({0.6, 0.5})}});
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "velocity probe 1 'u': the name is taken by probe 0");
  }
  const auto zone_message = [&](V<2> direction, double start, double end, double strength) {
    try {
      DampingZone<double, 2> zone(water.fluid, direction, start, end, strength);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(zone_message(vec<2>({0.0, 0.0}), 0, 1, 1), "damping zone: the direction must be finite and not zero");
  EXPECT_EQ(zone_message(vec<2>({1.0, 0.0}), 1, 1, 1),
            "damping zone: the end (1.000000) must be beyond the start (1.000000), both finite");
  EXPECT_EQ(zone_message(vec<2>({1.0, 0.0}), 0, 1, -1),
            "damping zone: the strength must be finite and >= 0 (it is -1.000000)");
  EXPECT_EQ(zone_message(vec<2>({1.0, 0.0}), 0, 1, 0), "no error");
}

// ---------------------------------------------------------------------------------------------
// Velocity probes

// A uniform velocity is read exactly wherever some water is within the support: inside, near the
// surface, near the side; a probe with no water within 2h is dry and reads 0.
TYPED_TEST(Measurements, VelocityProbeReadsAUniformFieldExactly) {
  const double dx = 0.1, depth = 10 * dx, width = 20 * dx;
  Water<2> water(lattice<2>({20, 10}, dx, [](const V<2>&) { return true; }), dx,
                 box_of<2>(vec<2>({-4 * dx, -4 * dx}), vec<2>({width + 10 * dx, 2.0})));
  const V<2> u = vec<2>({0.3, -0.7});
  {
    View<V<2>> v = water.fluid.velocity.write(MemorySpace::host);
    for (Index i = 0; i < v.size(); ++i) v[i] = u;
  }
  water.build(this->policy);
  VelocityProbes<double, 2> probes(water.fluid, water.cells, water.kernel,
                                   {{"inside", vec<2>({1.03, 0.41})},
                                    {"surface", vec<2>({0.77, depth + 0.2 * dx})},
                                    {"side", vec<2>({width + 2.0 * dx, 0.5})},
                                    {"dry", vec<2>({width + 3.0 * water.kernel.h, 0.5})}});
  const std::vector<VelocityReading<double, 2>> r = probes.measure(this->policy);
  ASSERT_EQ(r.size(), 4u);
  for (int p = 0; p < 3; ++p) {
    EXPECT_TRUE(r[std::size_t(p)].wet) << p;
    EXPECT_EQ(r[std::size_t(p)].velocity[0], u[0]) << p;
    EXPECT_EQ(r[std::size_t(p)].velocity[1], u[1]) << p;
  }
  EXPECT_NEAR(r[0].kernel_sum, 1.0, 0.02);
  EXPECT_LT(r[1].kernel_sum, 0.5);
  EXPECT_FALSE(r[3].wet);
  EXPECT_EQ(r[3].velocity[0], 0.0);
  EXPECT_EQ(r[3].velocity[1], 0.0);
  EXPECT_EQ(r[3].kernel_sum, 0.0);
  const std::vector<std::string> names = probes.column_names();
  ASSERT_EQ(names.size(), 8u);
  EXPECT_EQ(names[0], "velocity_inside_x");
  EXPECT_EQ(names[7], "velocity_dry_y");
}

// v = a + B x deep inside the water: exact to round-off at the points of lattice symmetry (a
// particle, a lattice corner, an edge's midpoint), within the lattice's first moment elsewhere
// (|x_bar - x| at most 0.0068 dx at h = 1.3 dx in 2D, so at most 0.0068 dx |B|).
TYPED_TEST(Measurements, VelocityProbeReadsALinearField) {
  const double dx = 0.1, width = 30 * dx, depth = 30 * dx;
  Water<2> water(lattice<2>({30, 30}, dx, [](const V<2>&) { return true; }), dx,
                 box_of<2>(vec<2>({-4 * dx, -4 * dx}), vec<2>({width + 4 * dx, depth + 4 * dx})));
  const V<2> a = vec<2>({0.2, -0.1});
  const double b[2][2] = {{0.7, -0.4}, {0.3, 1.1}};  // v_k = a_k + b[k][l] x_l
  const auto field = [&](const V<2>& x) {
    V<2> v = a;
    for (int k = 0; k < 2; ++k)
      for (int l = 0; l < 2; ++l) v[k] += b[k][l] * x[l];
    return v;
  };
  double b_norm = 0;  // the Frobenius norm, >= the spectral norm |B|
  for (const auto& row : b)
    for (double e : row) b_norm += e * e;
  b_norm = std::sqrt(b_norm);
  {
    View<const V<2>> x = water.fluid.position.read(MemorySpace::host);
    View<V<2>> v = water.fluid.velocity.write(MemorySpace::host);
    for (Index i = 0; i < v.size(); ++i) v[i] = field(x[i]);
  }
  water.build(this->policy);
  std::vector<VelocityProbePoint<double, 2>> symmetric{{"site", vec<2>({15.5 * dx, 14.5 * dx})},
                                                       {"corner", vec<2>({15 * dx, 15 * dx})},
                                                       {"edge", vec<2>({15 * dx, 14.5 * dx})}};
  std::vector<VelocityProbePoint<double, 2>> generic;
  for (int k = 0; k < 16; ++k)
    generic.push_back({numbered("p", k), vec<2>({(12 + 0.37 * k) * dx, (11 + 0.61 * ((k * 5) % 16)) * dx})});
  VelocityProbes<double, 2> exact(water.fluid, water.cells, water.kernel, symmetric);
  VelocityProbes<double, 2> elsewhere(water.fluid, water.cells, water.kernel, generic);
  const std::vector<VelocityReading<double, 2>> r = exact.measure(this->policy);
  for (std::size_t p = 0; p < r.size(); ++p) {
    const V<2> expected = field(symmetric[p].position);
    for (int k = 0; k < 2; ++k) EXPECT_NEAR(r[p].velocity[k], expected[k], 1e-13) << symmetric[p].name;
  }
  const std::vector<VelocityReading<double, 2>> s = elsewhere.measure(this->policy);
  double worst = 0;
  for (std::size_t p = 0; p < s.size(); ++p) {
    const V<2> expected = field(generic[p].position);
    worst = std::max(worst, std::sqrt(squared_norm(s[p].velocity - expected)) / (dx * b_norm));
  }
  std::printf("[ measured ] velocity probe, linear field inside the lattice: symmetric points exact to 1e-13; "
              "elsewhere |v - v(x)| <= %.5f dx |B|_F (16 points); bound 0.0068 dx |B|_F\n",
              worst);
  EXPECT_LT(worst, 0.0068);
}

// ---------------------------------------------------------------------------------------------
// Damping zone

// A uniform velocity in water 4 m long, the zone from 1.5 to 3.5 along x (given as (2, 0)):
// 40 steps of dt = 2e-3 at beta = 6. Inside, every particle's velocity is v0 times its factor
// to the 40th, bit for bit (the linear form's arithmetic is uncontracted, the same on every
// policy); outside, v0 bit for bit. The decay follows exp(-beta xi^2 t) within the linear form's
// second-order term; the neighbour records carry the new velocities.
TYPED_TEST(Measurements, DampingZoneDecaysAUniformFieldAtItsRate) {
  const double dx = 0.05, width = 4.0;
  Water<2> water(lattice<2>({80, 12}, dx, [](const V<2>&) { return true; }), dx,
                 box_of<2>(vec<2>({-4 * dx, -4 * dx}), vec<2>({width + 4 * dx, 1.0})));
  const V<2> v0 = vec<2>({0.8, -0.25});
  {
    View<V<2>> v = water.fluid.velocity.write(MemorySpace::host);
    for (Index i = 0; i < v.size(); ++i) v[i] = v0;
  }
  water.build(this->policy);
  // dt as exec() passes it (Real: float in single-precision builds), so the host's arithmetic matches.
  const double start = 1.5, end = 3.5, beta = 6.0, dt = double(Real(2e-3));
  const int steps = 40;
  for (DampingForm form : {DampingForm::linear, DampingForm::exponential}) {
    {
      View<V<2>> v = water.fluid.velocity.write(MemorySpace::host);
      for (Index i = 0; i < v.size(); ++i) v[i] = v0;
    }
    DampingZone<double, 2> zone(water.fluid, vec<2>({2.0, 0.0}), start, end, beta, form);
    EXPECT_EQ(zone.direction()[0], 1.0);
    for (int n = 0; n < steps; ++n) zone.exec(this->policy, dt);
    View<const V<2>> x = water.fluid.position.read(MemorySpace::host);
    View<const V<2>> v = water.fluid.velocity.read(MemorySpace::host);
    View<const VelocityPressure<double, 2>> records = water.fluid.neighbor_velocity_pressure.read(MemorySpace::host);
    Index inside = 0, outside = 0, mismatched = 0, off_rate = 0;
    double worst_rate = 0;
    const double t = steps * dt;
    for (Index i = 0; i < v.size(); ++i) {
      EXPECT_EQ(records[i].velocity, v[i]) << i;
      const double xi = zone.coordinate(x[i]);
      if (!(xi >= 0 && xi <= 1)) {
        ++outside;
        if (v[i] != v0) ++mismatched;
        continue;
      }
      ++inside;
      V<2> expected = v0;
      const double factor = damping_factor(xi, beta, dt, form);
      for (int n = 0; n < steps; ++n) expected = expected * factor;
      // The exponential form on the GPU: the device's exp, within 64 ulp after 40 steps.
      const bool exact = form == DampingForm::linear || TypeParam::space == MemorySpace::host;
      const auto close = [&](int a) {
        return std::abs(v[i][a] - expected[a]) <= 64 * std::numeric_limits<double>::epsilon() * std::abs(expected[a]);
      };
      if (exact ? v[i] != expected : !(close(0) && close(1))) ++mismatched;
      // The documented rate: v = v0 exp(-beta xi^2 t), the linear form within (beta xi^2)^2 dt t / 2.
      const double rate = beta * xi * xi;
      const double deviation = std::abs(v[i][0] / v0[0] - std::exp(-rate * t));
      const double bound = (form == DampingForm::linear ? 0.5 * rate * rate * dt * t * 1.01 : 0.0) + 1e-13;
      worst_rate = std::max(worst_rate, deviation);
      if (deviation > bound) ++off_rate;
    }
    EXPECT_GT(inside, 0u);
    EXPECT_GT(outside, 0u);
    EXPECT_EQ(mismatched, 0u) << (form == DampingForm::linear ? "linear" : "exponential");
    EXPECT_EQ(off_rate, 0u) << (form == DampingForm::linear ? "linear" : "exponential");
    std::printf("[ measured ] damping zone (%s form): %zu particles damped, %zu untouched, all as expected; "
                "largest |v/v0 - exp(-beta xi^2 t)| = %.3g at t = %.3g\n",
                form == DampingForm::linear ? "linear" : "exponential", std::size_t(inside), std::size_t(outside),
                worst_rate, t);
  }
}

// ---------------------------------------------------------------------------------------------
// Zone length, group velocity and strength (host)

TEST(HostMeasurements, ZoneLengthIsOneWaveLengthOfTheDispersionRelation) {
  double worst = 0;
  for (double period : {0.8, 1.5, 3.0, 10.0})
    for (double depth : {0.3, 0.6, 2.0, 10.0}) {
      const double length = damping_zone_length(period, depth, g);
      const double k = 2 * std::numbers::pi / length, omega = 2 * std::numbers::pi / period;
      const double residual = std::abs(g * k * std::tanh(k * depth) - omega * omega) / (omega * omega);
      worst = std::max(worst, residual);
      EXPECT_LT(residual, 1e-14) << period << " s, " << depth << " m";
      EXPECT_EQ(damping_zone_length(period, depth, g, 2.0), 2.0 * length);
      EXPECT_EQ(length, wave_length(period, depth, g));
    }
  // Deep water: g T^2 / (2 pi); shallow water: T sqrt(g d) (1 - (kd)^2 / 6 + ...).
  EXPECT_NEAR(damping_zone_length(1.0, 1e3, g), g / (2 * std::numbers::pi), 1e-12);
  const double shallow = damping_zone_length(10.0, 1e-3, g), celerity = std::sqrt(g * 1e-3) * 10.0;
  EXPECT_NEAR(shallow / celerity, 1.0, 1e-5);
  std::printf("[ measured ] zone length: |g k tanh kd - w^2| / w^2 <= %.2g over 16 periods and depths\n", worst);
}

TEST(HostMeasurements, GroupVelocityAndStrengthEstimate) {
  for (double period : {0.8, 1.5, 3.0})
    for (double depth : {0.3, 0.6, 2.0}) {
      const double omega = 2 * std::numbers::pi / period, k = wave_number(omega, depth, g);
      const double step = 1e-5 * k;
      const double derivative =
          (dispersion_frequency(k + step, depth, g) - dispersion_frequency(k - step, depth, g)) / (2 * step);
      EXPECT_NEAR(wave_group_velocity(period, depth, g) / derivative, 1.0, 1e-8) << period << " s, " << depth << " m";
    }
  // Limits: c/2 in deep water, sqrt(g d) in shallow water.
  EXPECT_NEAR(wave_group_velocity(1.0, 1e3, g) / (0.5 * g / (2 * std::numbers::pi)), 1.0, 1e-12);
  EXPECT_NEAR(wave_group_velocity(100.0, 1e-3, g) / std::sqrt(g * 1e-3), 1.0, 1e-6);
  EXPECT_NEAR(wave_group_velocity(1.0, std::numeric_limits<double>::infinity(), g), 0.5 * g / (2 * std::numbers::pi),
              1e-15);
  // The strength for a round-trip factor, and back.
  const double period = 1.5, depth = 0.6, zone = damping_zone_length(period, depth, g);
  const double beta = damping_strength_for(0.01, zone, period, depth, g);
  EXPECT_NEAR(damping_round_trip_amplitude(beta, zone, period, depth, g), 0.01, 1e-15);
  EXPECT_NEAR(beta, 3 * wave_group_velocity(period, depth, g) * std::log(100.0) / zone, 1e-12);
  std::printf("[ measured ] T = 1.5 s, d = 0.6 m: L = %.4f m, c_g = %.4f m/s, beta for 1 %% round trip over L = %.3f 1/s "
              "(%.2f w)\n",
              zone, wave_group_velocity(period, depth, g), beta, beta * period / (2 * std::numbers::pi));
}
