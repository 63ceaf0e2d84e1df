// Periodic axes in the solver (case domain.periodic; neighbor/periodic_images.hpp), on every
// policy:
//  * policies agree: 200 advection steps of a drifting shear wave in the Taylor-Green case's
//    periodic box (dx = 1/50) on seq, par and the GPU within 1e-9 relative (double), its energy
//    decaying at the viscous rate; observers count owned particles only; a checkpoint restores
//    the run bit for bit on seq;
//  * a lattice at rest in a periodic box stays at rest to round-off (no face is felt);
//  * with fluid.kernel_gradient_correction the shear wave's total momentum is kept to round-off
//    (the corrected pairs are antisymmetric, images included);
//  * broken periodic cases are refused with one line naming the file, the line and the key;
//  * the Taylor-Green vortex at Re = 100 on 100 x 100 particles to t = 0.1 against SPHinXsys'
//    regression records of the same case (E_k(0.1) / E_k(0) within 2 %): on the lattice against its
//    lattice record, from particles relaxed in the periodic box (the case file's start, even across
//    the faces) against its record of a reloaded start;
//  * validation (label `validation`, ctest -L validation): the Taylor-Green vortex at Re = 100 on
//    100 x 100 particles relaxed in the box (kinetic-energy decay rate against exp(-16 pi^2 t / Re),
//    within 5 %; printed beside SPHinXsys' records) and
//    Poiseuille flow at Re = 1 between plates driven by a body force (the profile within 2 % of
//    the parabola). Each prints its figure beside its bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "support/by_id.hpp"
#include "support/case_text.hpp"
#include "support/policy_test.hpp"
#include "unisph/solver/case_file.hpp"
#include "unisph/smoothing/wendland_kernel.hpp"
#include "unisph/solver/weakly_compressible_solver.hpp"

using namespace unisph;
using namespace unisph::sph;
using unisph::testing::file_text;
using unisph::testing::by_id;
using unisph::testing::kind_of;
using unisph::testing::replaced;

namespace {

const std::string taylor_green_path = std::string(UNISPH_CASES_DIR) + "/taylor_green_2d.toml";

// The Taylor-Green case as its file describes it (particles relaxed in the periodic box, shifted
// every advection step, the direct search) with the vortex's velocity at each particle and p = 0
// (as SPHinXsys' runs start; U = 1, rho = 1), optionally at another spacing.
CaseDescription taylor_green(const std::string& dx = "") {
  std::string text = file_text(taylor_green_path);
  if (!dx.empty()) text = replaced(text, "dx = 0.01 ", "dx = " + dx + " ");
  CaseDescription c = parse_case(text, "taylor_green_2d.toml");
  c.initial_fluid_state = [](const std::vector<double>& x, std::vector<double>& v, double& p) {
    const double pi = std::numbers::pi;
    v[0] = -std::cos(2 * pi * x[0]) * std::sin(2 * pi * x[1]);
    v[1] = std::sin(2 * pi * x[0]) * std::cos(2 * pi * x[1]);
    p = 0;
  };
  return c;
}

// The same box on the lattice x = (i + 1/2) dx, without shifting, with the solver's default search
// and the analytic initial pressure: the checks below that compare bits, momentum or a lattice at
// rest, and SPHinXsys' record of its own lattice start.
CaseDescription taylor_green_lattice(const std::string& dx = "") {
  CaseDescription c = taylor_green(dx);
  c.bodies[0].fill = "lattice";
  c.particle_shifting = 0;
  c.neighbor_search = "automatic";
  c.initial_fluid_state = [](const std::vector<double>& x, std::vector<double>& v, double& p) {
    const double pi = std::numbers::pi;
    v[0] = -std::cos(2 * pi * x[0]) * std::sin(2 * pi * x[1]);
    v[1] = std::sin(2 * pi * x[0]) * std::cos(2 * pi * x[1]);
    p = -0.25 * (std::cos(4 * pi * x[0]) + std::cos(4 * pi * x[1]));
  };
  return c;
}

// SPHinXsys' regression records of the same Taylor-Green case (tests/data/validation/): kinetic
// energy at t = 0, 0.1, ..., 1. "kinetic_energy" (commit 4c3c916d) started on the lattice and
// breaks down after t = 0.1 as unisph does from the lattice; "mechanical_energy" (commit
// 99fe19c0) started from reloaded, disordered particles (its E0 is 0.25015, where the lattice gives
// 0.25 exactly) and follows the analytic decay (the files name each commit and its methods).
std::vector<double> sphinxsys_taylor_green_energy(const std::string& record = "kinetic_energy") {
  std::istringstream in(
      file_text(std::string(UNISPH_VALIDATION_DATA_DIR) + "/sphinxsys_2d_taylor_green_" + record + ".csv"));
  std::vector<double> energy;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    energy.push_back(std::stod(line.substr(line.find(',') + 1)));
  }
  return energy;
}

}  // namespace

UNISPH_POLICY_TEST_SUITE(Periodic);

// The Taylor-Green vortex (Re = 100, 100 x 100) to t = 0.1 against SPHinXsys' record of the same
// case: E_k(0.1) / E_k(0) within 2 % of its 0.8259 (the analytic decay gives 0.8539; both codes
// fall below it from the start, and past t = 0.1 both break down: docs/sph.md, "Periodic axes").
// seq and par (stored lists, as SPHinXsys) give 0.8258; the GPU's direct search, whose pair
// geometry follows every acoustic step, 0.8172 (H100, session 13).
TYPED_TEST(Periodic, TaylorGreenFollowsSphinxsysRecordToTimeOneTenth) {
  WeaklyCompressibleSolver<double, 2> solver(taylor_green_lattice(), kind_of<TypeParam>());
  const double start = solver.observe().kinetic_energy;
  while (solver.time() < 0.1 * (1 - 1e-12)) solver.advance(0.1);
  const double ratio = solver.observe().kinetic_energy / start;
  const std::vector<double> record = sphinxsys_taylor_green_energy();
  ASSERT_EQ(record.size(), 11u);
  const double reference = record[1] / record[0];
  std::printf("%s Taylor-Green E_k(0.1) / E_k(0): %.4f; SPHinXsys' record %.4f (%.2f %% apart, bound 2 %%); analytic %.4f\n",
              std::string(TypeParam::test_label).c_str(), ratio, reference, 100 * (ratio / reference - 1),
              std::exp(-16 * std::numbers::pi * std::numbers::pi / 100 * 0.1));
  EXPECT_NEAR(ratio / reference, 1.0, 0.02);
}

// The case file's start: 10,000 particles relaxed in the periodic box (fill = "relaxed"), even
// across its faces — each particle's kernel sum, its neighbours beyond the faces counted, within
// 2 % of the lattice's (a relaxation that met the faces as surfaces packs the particles against
// them, and their sums come out higher there) — then E_k(0.1) / E_k(0) within 2 % of SPHinXsys'
// record of its reloaded, disordered start (commit 99fe19c0: 0.8542; analytic 0.8539).
TYPED_TEST(Periodic, TaylorGreenFromRelaxedParticlesFollowsTheRegularRecordToTimeOneTenth) {
  WeaklyCompressibleSolver<double, 2> solver(taylor_green(), kind_of<TypeParam>());
  ASSERT_EQ(solver.fluid_count(), 100 * 100);
  const auto x = by_id<Vec<double, 2>>(solver.fluid_body(), "Position");
  const double dx = 0.01;
  const auto kernel = WendlandC2Kernel<double, 2>::from_spacing(dx, solver.smoothing_length() / dx);
  const double lattice = kernel.lattice_sum(dx);
  double worst = 0, worst_at_faces = 0, mean = 0, square = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    double sum = 0;
    for (std::size_t j = 0; j < x.size(); ++j) {
      double a = x[j][0] - x[i][0], b = x[j][1] - x[i][1];
      a -= std::round(a), b -= std::round(b);  // the nearest image in the unit box
      sum += kernel.value(std::sqrt(a * a + b * b));
    }
    const double off = std::abs(sum / lattice - 1);
    mean += sum / lattice, square += (sum / lattice) * (sum / lattice);
    worst = std::max(worst, off);
    const double to_face = std::min({x[i][0], 1 - x[i][0], x[i][1], 1 - x[i][1]});
    if (to_face < kernel.cutoff()) worst_at_faces = std::max(worst_at_faces, off);
  }
  mean /= double(x.size());
  const double spread = std::sqrt(std::max(0.0, square / double(x.size()) - mean * mean));
  const double start = solver.observe().kinetic_energy;
  while (solver.time() < 0.1 * (1 - 1e-12)) solver.advance(0.1);
  const double ratio = solver.observe().kinetic_energy / start;
  const std::vector<double> record = sphinxsys_taylor_green_energy("mechanical_energy");
  const double reference = record[1] / record[0];
  std::printf("%s Taylor-Green from relaxed particles: kernel sums %.4f +- %.4f of the lattice's, within %.2f %% of it "
              "(%.2f %% within a cutoff of a face); E_k(0.1) / E_k(0) %.4f, SPHinXsys' regular record %.4f (%.2f %% apart, "
              "bound 2 %%)\n",
              std::string(TypeParam::test_label).c_str(), mean, spread, 100 * worst, 100 * worst_at_faces, ratio, reference,
              100 * (ratio / reference - 1));
  EXPECT_LT(worst, 0.02);
  EXPECT_NEAR(ratio / reference, 1.0, 0.02);
}

// The Taylor-Green case's box (dx = 1/50) with a shear wave drifting along y: u = sin(2 pi y),
// v = 0.3, so particles cross both pairs of faces. (The Taylor-Green field itself breaks down
// after t = 0.1 with this method, docs/sph.md "Periodic axes", and chaotic motion would amplify
// the par order of summation within a cell to more than 1e-9.) The kinetic energy of the wave
// decays as exp(-8 pi^2 nu t) (nu = 0.01) around the constant drift.
TYPED_TEST(Periodic, ShearWaveAgreesWithSeqAndDecays) {
  if (sizeof(Real) == 4)
    GTEST_SKIP() << "this build computes shapes in unisph::Real = float (UNISPH_SINGLE_PRECISION): the lattice this check "
                    "compares to the last bit of double is not the same (docs/sph.md, \"The general form\")";
  CaseDescription c = taylor_green_lattice("0.02");
  // The same method on every policy: "automatic" would take stored lists on the CPU and the
  // direct search (geometry of every acoustic step) on the GPU.
  c.neighbor_search = "stored";
  c.initial_fluid_state = [](const std::vector<double>& x, std::vector<double>& v, double& p) {
    v[0] = std::sin(2 * std::numbers::pi * x[1]);
    v[1] = 0.3;
    p = 0;
  };
  WeaklyCompressibleSolver<double, 2> reference(c, PolicyKind::seq);
  WeaklyCompressibleSolver<double, 2> solver(c, kind_of<TypeParam>());
  ASSERT_EQ(solver.fluid_count(), 50 * 50);
  ASSERT_EQ(solver.wall_count(), 0);
  const ObserverSample start = solver.observe();
  EXPECT_NEAR(start.kinetic_energy, 0.25 + 0.5 * 0.09, 1e-12) << "sum m v^2 / 2 over owned particles only";
  for (int step = 0; step < 200; ++step) {
    reference.advance(1e9);
    solver.advance(1e9);
  }
  ASSERT_EQ(solver.fluid_count(), 50 * 50) << "owned particles: wrapped, never removed";
  EXPECT_EQ(solver.left_domain_count(), 0);
  const auto x = by_id<Vec<double, 2>>(solver.fluid_body(), "Position");
  const auto x_ref = by_id<Vec<double, 2>>(reference.fluid_body(), "Position");
  const auto v = by_id<Vec<double, 2>>(solver.fluid_body(), "Velocity");
  const auto v_ref = by_id<Vec<double, 2>>(reference.fluid_body(), "Velocity");
  double position = 0, velocity = 0, speed = 0, outside = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (int a = 0; a < 2; ++a) {
      // Positions wrap: compare the minimum image (1 = the box's side).
      double d = std::abs(x[i][a] - x_ref[i][a]);
      position = std::max(position, std::min(d, 1 - d));
      velocity = std::max(velocity, std::abs(v[i][a] - v_ref[i][a]));
      speed = std::max(speed, std::abs(v_ref[i][a]));
      outside = std::max({outside, -x[i][a], x[i][a] - 1.0});
    }
  const ObserverSample a = reference.observe(), b = solver.observe();
  const double wave = b.kinetic_energy - 0.5 * 0.09, expected = 0.25 * std::exp(-8 * std::numbers::pi * std::numbers::pi * 0.01 * b.time);
  std::printf("%s after 200 advection steps (t = %.4f): position %.3g, velocity %.3g relative to seq; wave energy %.6f against "
              "%.6f analytic (%.2f %%), mass %.15g\n",
              std::string(TypeParam::test_label).c_str(), solver.time(), position, velocity / speed, wave, expected,
              100 * (wave / expected - 1), b.mass);
  EXPECT_EQ(solver.advection_steps(), reference.advection_steps());
  EXPECT_NEAR(solver.time(), reference.time(), 1e-12 * reference.time()) << "steps from the largest speed, to round-off";
  EXPECT_LE(position, 1e-9);
  EXPECT_LE(velocity / speed, 1e-9);
  EXPECT_LE(outside, 0.0) << "owned particles are wrapped into the box after every step";
  EXPECT_NEAR(b.kinetic_energy, a.kinetic_energy, 1e-9 * a.kinetic_energy);
  EXPECT_NEAR(b.mass, start.mass, 1e-12 * start.mass) << "no mass gained or lost across the faces";
  // The viscous operator alone gives the rate to 0.03 % here (measured with the Riemann pressure
  // dissipation switched off); the dissipation, active on the approaching diagonal pairs of the
  // shear, adds 2.6 % (docs/sph.md, "Periodic axes").
  EXPECT_NEAR(wave / expected, 1.0, 0.03) << "the shear wave decays at the viscous rate";
}

// fluid.kernel_gradient_correction keeps the momentum equation's pairs antisymmetric, (p_i B_i +
// p_j B_j) seen from i and from j: in a periodic box without walls or gravity the total momentum
// stays what it was to round-off, pairs across the faces included (their B_j is the image's copy
// of its source's). The shear wave drifts across the faces during the 50 advection steps.
TYPED_TEST(Periodic, KernelGradientCorrectionConservesMomentum) {
  CaseDescription c = taylor_green_lattice("0.02");
  c.kernel_gradient_correction = true;
  // The stored lists on every policy: each pair's geometry fixed at the list's build, the same
  // seen from i and from j. The direct search measures it anew from the current positions, and
  // an image's position (its source's plus the period, rounded) is not exactly the source's
  // shifted: it keeps the momentum to 1.5e-11 of |P| on this CPU and 4.3e-8 on an H100 (session
  // 21; the GPU's larger drift is not explained).
  c.neighbor_search = "stored";
  c.initial_fluid_state = [](const std::vector<double>& x, std::vector<double>& v, double& p) {
    v[0] = std::sin(2 * std::numbers::pi * x[1]);
    v[1] = 0.3;
    p = 0;
  };
  WeaklyCompressibleSolver<double, 2> solver(c, kind_of<TypeParam>());
  const auto momentum = [&] {
    const auto v = by_id<Vec<double, 2>>(solver.fluid_body(), "Velocity");
    const auto m = by_id<double, double, 2>(solver.fluid_body(), "Mass");
    Vec<double, 2> total{};
    for (std::size_t i = 0; i < v.size(); ++i) total += v[i] * m[i];
    return total;
  };
  const Vec<double, 2> before = momentum();
  for (int step = 0; step < 50; ++step) solver.advance(1e9);
  const Vec<double, 2> after = momentum();
  std::printf("%s periodic shear wave with the kernel gradient corrected, 50 advection steps (t = %.3f): momentum "
              "(%.3e, %.6f) -> (%.3e, %.6f), change %.2e (bound 1e-12 of |P|)\n",
              std::string(TypeParam::test_label).c_str(), solver.time(), before[0], before[1], after[0], after[1],
              norm(after - before));
  EXPECT_LE(norm(after - before), 1e-12 * norm(before));
}

TYPED_TEST(Periodic, LatticeAtRestStaysAtRestAndProbesSeeAcrossFaces) {
  if (sizeof(Real) == 4)
    GTEST_SKIP() << "this build computes shapes in unisph::Real = float (UNISPH_SINGLE_PRECISION): the lattice this check "
                    "compares to the last bit of double is not the same (docs/sph.md, \"The general form\")";
  // Fluid at rest at rho0 fills the periodic box: every particle has a full, uniform
  // neighbourhood across the faces, so nothing moves (a face that was not periodic would push).
  std::string text = file_text(taylor_green_path);
  text = replaced(text, "dx = 0.01 ", "dx = 0.05 ");
  text += "\n[[probe]]\nname = \"corner\"\nposition = [0.0, 0.0]\n[[probe]]\nname = \"middle\"\nposition = [0.5, 0.5]\n";
  CaseDescription c = parse_case(text, "taylor_green_2d.toml");
  c.bodies[0].fill = "lattice";
  c.particle_shifting = 0;
  c.neighbor_search = "automatic";
  c.initial_fluid_state = [](const std::vector<double>&, std::vector<double>&, double& p) { p = 1.0; };
  WeaklyCompressibleSolver<double, 2> solver(c, kind_of<TypeParam>());
  ASSERT_EQ(solver.fluid_count(), 20 * 20);
  for (int step = 0; step < 20; ++step) solver.advance(1e9);
  const ObserverSample s = solver.observe();
  std::printf("%s: at rest after 20 steps: kinetic energy %.3g; probe at the corner %.15g, in the middle %.15g\n",
              std::string(TypeParam::test_label).c_str(), s.kinetic_energy, s.probe_pressure[0], s.probe_pressure[1]);
  EXPECT_LT(s.kinetic_energy, 1e-20);
  // The corner probe sees the four corners' particles (three of them as images): the same
  // pressure as the middle.
  EXPECT_NEAR(s.probe_pressure[0], s.probe_pressure[1], 1e-12);
  EXPECT_NEAR(s.probe_pressure[1], 1.0, 1e-9);
}

TYPED_TEST(Periodic, CheckpointRestoresWithoutImages) {
  if (sizeof(Real) == 4)
    GTEST_SKIP() << "this build computes shapes in unisph::Real = float (UNISPH_SINGLE_PRECISION): the lattice this check "
                    "compares to the last bit of double is not the same (docs/sph.md, \"The general form\")";
  if (kind_of<TypeParam>() != PolicyKind::seq) GTEST_SKIP() << "bit-for-bit continuation is a seq property";
  const CaseDescription c = taylor_green_lattice("0.04");
  const auto dir = std::filesystem::temp_directory_path() / ("unisph_periodic_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto file = dir / "checkpoint.bin";
  WeaklyCompressibleSolver<double, 2> a(c, PolicyKind::seq);
  for (int step = 0; step < 20; ++step) a.advance(1e9);
  a.write_checkpoint(file);
  WeaklyCompressibleSolver<double, 2> b(c, PolicyKind::seq, false);
  b.restore_checkpoint(file);
  EXPECT_EQ(b.fluid_count(), a.fluid_count());
  for (int step = 0; step < 20; ++step) a.advance(1e9), b.advance(1e9);
  const auto xa = by_id<Vec<double, 2>>(a.fluid_body(), "Position"), xb = by_id<Vec<double, 2>>(b.fluid_body(), "Position");
  double worst = 0;
  for (std::size_t i = 0; i < xa.size(); ++i) worst = std::max({worst, std::abs(xa[i][0] - xb[i][0]), std::abs(xa[i][1] - xb[i][1])});
  EXPECT_EQ(worst, 0.0);
  // Another case's checkpoint (no periodic axes) is refused by name.
  CaseDescription closed = c;
  closed.domain.periodic = {0};
  WeaklyCompressibleSolver<double, 2> other(closed, PolicyKind::seq, false);
  try {
    other.restore_checkpoint(file);
    ADD_FAILURE() << "a checkpoint of other periodic axes was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("domain.periodic"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

// Bad periodic input: one line naming the file, the line and the key.
TEST(HostPeriodic, BrokenCasesAreRefusedWithOneLine) {
  const std::string tg = file_text(taylor_green_path);
  const std::string channel = file_text(std::string(UNISPH_CASES_DIR) + "/poiseuille_2d.toml");
  struct Broken {
    std::string text, expected;
  };
  const std::vector<Broken> parse_errors = {
      {replaced(tg, "periodic = [\"x\", \"y\"]", "periodic = [\"x\", \"w\"]"),
       "taylor_green_2d.toml:26: key 'domain.periodic': \"w\" is not an axis of this 2D case (\"x\" or \"y\")"},
      {replaced(tg, "periodic = [\"x\", \"y\"]", "periodic = [\"z\"]"), "key 'domain.periodic': \"z\" is not an axis of this 2D case"},
      {replaced(tg, "periodic = [\"x\", \"y\"]", "periodic = [\"y\", \"y\"]"),
       "taylor_green_2d.toml:26: key 'domain.periodic': axis \"y\" is named twice"},
      {replaced(tg, "periodic = [\"x\", \"y\"]", "periodic = \"x\""), "key 'domain.periodic': must be an array of axis names"},
      {replaced(tg, "periodic = [\"x\", \"y\"]", "periodic = [0]"), "key 'domain.periodic': entries must be axis names"},
      {replaced(tg, "periodic = [\"x\", \"y\"]\n", ""), "key 'physics.gravity': must not be the zero vector"},
      {replaced(channel, "kind = \"wall\"\nshape = \"lower_plate\"\n", "kind = \"wall\"\nshape = \"lower_plate\"\nfill = \"relaxed\"\n"),
       "key 'body.fill': relaxed wall bodies are not available in a periodic domain"},
  };
  for (const Broken& b : parse_errors) {
    try {
      parse_case(b.text, "taylor_green_2d.toml");
      ADD_FAILURE() << "accepted; expected: " << b.expected;
    } catch (const CaseFileError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(b.expected), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      EXPECT_EQ(what.rfind("taylor_green_2d.toml:", 0), 0u) << what;
    }
  }
  // Errors found when the solver is made (they depend on the run's dx).
  const std::vector<Broken> solver_errors = {
      // 5 dx wide along x: less than two cutoffs (5.2 dx).
      {replaced(replaced(tg, "upper = [1.0, 1.0]\nperiodic", "upper = [0.05, 1.0]\nperiodic"), "upper = [1.0, 1.0]\n\n[[body]]",
                "upper = [0.05, 1.0]\n\n[[body]]"),
       "taylor_green_2d.toml:26: key 'domain.periodic': the domain is 0.05 wide along periodic axis x, narrower than two cutoffs"},
      {replaced(replaced(tg, "upper = [1.0, 1.0]\nperiodic", "upper = [1.005, 1.0]\nperiodic"), "upper = [1.0, 1.0]\n\n[[body]]",
                "upper = [1.005, 1.0]\n\n[[body]]"),
       "key 'domain.periodic': the domain's length along periodic axis x (1.005) is not a whole number of particle spacings"},
      // The channel made periodic along y too: the plates lie across it.
      {replaced(channel, "periodic = [\"x\"]", "periodic = [\"x\", \"y\"]"),
       "key 'domain.periodic': wall body 'lower_plate' lies across periodic axis y"},
      // A plate that ends at the periodic face instead of running through it.
      {replaced(channel, "lower = [-1.0, -0.5]\nupper = [1.4, 0.0]", "lower = [0.1, -0.5]\nupper = [1.4, 0.0]"),
       "key 'domain.periodic': wall body 'lower_plate' lies across periodic axis x"},
      // Relaxed water between the plates: the plates' surfaces lie within reach (a periodic
      // relaxation is built for a fluid that fills the domain).
      {replaced(channel, "kind = \"fluid\"\nshape = \"channel\"\n", "kind = \"fluid\"\nshape = \"channel\"\nfill = \"relaxed\"\n"),
       "key 'body.shape' (body 'water'): shape: a relaxed fluid in a periodic domain must fill it with no surface within"},
  };
  for (const Broken& b : solver_errors) {
    const std::string name = b.text.find("poiseuille") != std::string::npos ? "poiseuille_2d.toml" : "taylor_green_2d.toml";
    try {
      WeaklyCompressibleSolver<double, 2> solver(parse_case(b.text, name), PolicyKind::seq);
      ADD_FAILURE() << "accepted; expected: " << b.expected;
    } catch (const CaseFileError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(b.expected), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      EXPECT_EQ(what.rfind(name + ":", 0), 0u) << what;
    }
  }
  // Each wall particle's averaged pressure (fluid.wall_pressure = "averaged") is not carried
  // across periodic faces: the solver refuses the case with one line.
  try {
    WeaklyCompressibleSolver<double, 2> solver(
        parse_case(replaced(channel, "[fluid]\n", "[fluid]\nwall_pressure = \"averaged\"\n"), "poiseuille_2d.toml"),
        PolicyKind::seq);
    ADD_FAILURE() << "fluid.wall_pressure = \"averaged\" accepted with periodic axes";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("fluid.wall_pressure = \"averaged\" runs on one rank without periodic axes"), std::string::npos)
        << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_EQ(what.rfind("poiseuille_2d.toml:", 0), 0u) << what;  // the file and the line of domain.periodic
  }
}

// ---- validation (DISABLED_: run by the `validation` ctest entries with --gtest_also_run_disabled_tests)

UNISPH_POLICY_TEST_SUITE(PeriodicValidation);

TYPED_TEST(PeriodicValidation, DISABLED_TaylorGreenDecayRate) {
  const auto start_clock = std::chrono::steady_clock::now();
  WeaklyCompressibleSolver<double, 2> solver(taylor_green(), kind_of<TypeParam>());
  ASSERT_EQ(solver.fluid_count(), 100 * 100);
  // Least-squares fit of log E_k against t over [0, 1], sampled every 0.02.
  std::vector<double> t, log_e;
  for (int k = 0; k <= 50; ++k) {
    const double until = 0.02 * k;
    while (solver.time() < until * (1 - 1e-12)) solver.advance(until);
    const ObserverSample s = solver.observe();
    t.push_back(s.time);
    log_e.push_back(std::log(s.kinetic_energy));
  }
  double mt = 0, me = 0;
  for (std::size_t k = 0; k < t.size(); ++k) mt += t[k], me += log_e[k];
  mt /= double(t.size()), me /= double(t.size());
  double stt = 0, ste = 0;
  for (std::size_t k = 0; k < t.size(); ++k) stt += (t[k] - mt) * (t[k] - mt), ste += (t[k] - mt) * (log_e[k] - me);
  const double rate = -ste / stt;
  const double analytic = 16 * std::numbers::pi * std::numbers::pi / 100.0;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_clock).count();
  std::printf("%s Taylor-Green Re = 100, 100 x 100: decay rate of E_k %.5f against 16 pi^2 / Re = %.5f: error %.2f %% "
              "(bound 5 %%); E_k(1) / E_k(0) = %.5f (analytic %.5f); %llu advection, %llu acoustic steps, %.1f s\n",
              std::string(TypeParam::test_label).c_str(), rate, analytic, 100 * std::abs(rate / analytic - 1),
              std::exp(log_e.back() - log_e.front()), std::exp(-analytic), (unsigned long long)solver.advection_steps(),
              (unsigned long long)solver.acoustic_steps(), seconds);
  // SPHinXsys' two records of the same case, fitted the same way (their 11 samples, every 0.1).
  const std::vector<double> record = sphinxsys_taylor_green_energy();
  const std::vector<double> regular = sphinxsys_taylor_green_energy("mechanical_energy");
  ASSERT_EQ(regular.size(), record.size());
  const auto fitted_rate = [](const std::vector<double>& e) {
    double rt = 0, re = 0, rtt = 0, rte = 0;
    for (std::size_t k = 0; k < e.size(); ++k) rt += 0.1 * double(k), re += std::log(e[k]);
    rt /= double(e.size()), re /= double(e.size());
    for (std::size_t k = 0; k < e.size(); ++k)
      rtt += (0.1 * double(k) - rt) * (0.1 * double(k) - rt), rte += (0.1 * double(k) - rt) * (std::log(e[k]) - re);
    return -rte / rtt;
  };
  std::printf("%s E_k(t) / E_k(0), unisph [SPHinXsys' records 4c3c916d / 99fe19c0] (analytic):",
              std::string(TypeParam::test_label).c_str());
  for (std::size_t k = 5; k < t.size(); k += 5)
    std::printf(" t = %.1f: %.4f [%.4f / %.4f] (%.4f)", t[k], std::exp(log_e[k] - log_e.front()), record[k / 5] / record[0],
                regular[k / 5] / regular[0], std::exp(-analytic * t[k]));
  std::printf("; SPHinXsys' decay rates %.5f / %.5f (%.2f / %.2f %% from the analytic)\n", fitted_rate(record),
              fitted_rate(regular), 100 * std::abs(fitted_rate(record) / analytic - 1),
              100 * std::abs(fitted_rate(regular) / analytic - 1));
  EXPECT_LT(std::abs(rate / analytic - 1), 0.05);
}

TYPED_TEST(PeriodicValidation, DISABLED_PoiseuilleProfile) {
  const auto start_clock = std::chrono::steady_clock::now();
  const CaseDescription c = read_case_file(std::string(UNISPH_CASES_DIR) + "/poiseuille_2d.toml");
  WeaklyCompressibleSolver<double, 2> solver(c, kind_of<TypeParam>());
  const double g = c.gravity_vector[0], nu = c.viscosity / c.density, height = 1.0;
  const double u_max = g * height * height / (8 * nu);
  while (solver.time() < c.end_time * (1 - 1e-12)) solver.advance(c.end_time);
  const auto x = by_id<Vec<double, 2>>(solver.fluid_body(), "Position");
  const auto v = by_id<Vec<double, 2>>(solver.fluid_body(), "Velocity");
  // Mean u of each lattice row (particles keep their rows in this flow) and the worst particle.
  const double dx = c.dx;
  const int rows = int(std::lround(height / dx));
  std::vector<double> sum(std::size_t(rows), 0.0);
  std::vector<int> count(std::size_t(rows), 0);
  double worst_particle = 0, cross = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double y = x[i][1];
    const double exact = g * y * (height - y) / (2 * nu);
    worst_particle = std::max(worst_particle, std::abs(v[i][0] - exact) / u_max);
    cross = std::max(cross, std::abs(v[i][1]) / u_max);
    const int row = std::clamp(int(std::floor(y / dx)), 0, rows - 1);
    sum[std::size_t(row)] += v[i][0] - exact;
    ++count[std::size_t(row)];
  }
  double worst_row = 0;
  for (int r = 0; r < rows; ++r)
    if (count[std::size_t(r)] > 0) worst_row = std::max(worst_row, std::abs(sum[std::size_t(r)] / count[std::size_t(r)]) / u_max);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_clock).count();
  std::printf("%s Poiseuille Re = %.2f, %d particles across, t = %.2f (%.2f H^2/nu): row-mean profile error %.3f %% of u_max "
              "(bound 2 %%), worst particle %.3f %%, largest |v| %.3g u_max; %llu advection steps, %.1f s\n",
              std::string(TypeParam::test_label).c_str(), u_max * height / nu, rows, solver.time(), solver.time() * nu / (height * height),
              100 * worst_row, 100 * worst_particle, cross, (unsigned long long)solver.advection_steps(), seconds);
  EXPECT_LT(worst_row, 0.02);
}
