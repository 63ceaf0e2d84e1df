// The SPH solver on several ranks against the same case on one: the 2D and 3D dam break, 200
// advection steps on each policy, the particle states gathered by id and compared with the run
// on one rank (made by rank 0 alone), and the observers (energies, mass, front, the wall probe,
// two wave gauges and a velocity probe) that every rank reports for the whole fluid. The water crosses subdomains (particles migrate)
// and the counts drift apart (the domain is cut anew). Run without mpirun (1 rank: the two runs
// must have the same bits), under mpirun -np 2 and -np 4. On the host policies the states of 2
// and 4 ranks must have the one rank's bits too: every neighbour sum visits cells in a fixed
// order and the particles of a cell by global id (CellLinkedList::order_within_cells_by_id),
// and the time step is an exact max; the gauges and the velocity probe are read by the rank that
// owns their points, as on one rank. The observers summed over ranks (energies, mass, the
// pressure probe) are not bit-equal: their sums are grouped by rank.
#include <gtest/gtest.h>

#include <mpi.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <cstdio>
#include <sstream>
#include <thread>
#include <vector>

#include "support/policy_test.hpp"
#include "support/small_dam_break.hpp"
#include "unisph/comm/communicator.hpp"
#include "unisph/solver/case_file.hpp"
#include "unisph/solver/weakly_compressible_solver.hpp"

namespace {
using namespace unisph;
using namespace unisph::sph;
using unisph::testing::kind_of;

// The shared small dam break in a lower tank (2D: 3 H high), to t = 100, with the probe under
// the column (hydrostatic, then falling).
CaseDescription small_dam_break(int dimension) {
  CaseDescription c = unisph::testing::small_dam_break(dimension);
  c.tank[1] = dimension == 2 ? 3.0 : 2.0;
  c.end_time = 100;
  c.output_interval = 100;
  c.probes[0].name = "left";
  c.probes[0].position[0] = 0.0;
  // Gauges through the column and where the water runs (their lines cross subdomains), and a
  // velocity probe in the column's foot: read on several ranks by each point's owner.
  const double z = 0.25;  // 3D: across the tank's middle
  c.gauges = {{"column", {1.0, 0.0}, 0.0, 2.0, 0}, {"run", {3.0, 0.0}, 0.0, 1.5, 0}};
  c.velocity_probes = {{"foot", {1.5, 0.3}}};
  if (dimension == 3) {
    for (auto& g : c.gauges) g.position.push_back(z);
    c.velocity_probes[0].position.push_back(z);
  }
  return c;
}

// A column collapsing on a floor in a domain periodic along x (3D: along x and z): the water
// runs out both ways and through the periodic faces, where it meets itself; the floor runs
// through the faces. A pressure probe, a gauge and a velocity probe beside the faces read the
// images across them.
CaseDescription periodic_collapse(int dimension) {
  const bool three = dimension == 3;
  std::ostringstream t;
  t << "[case]\nname = \"periodic_collapse\"\ndimension = " << dimension << "\n"
    << "[geometry]\ndx = " << (three ? "0.1" : "0.05") << "\n"
    << "[domain]\nlower = [0.0, -0.25" << (three ? ", 0.0" : "") << "]\nupper = [4.0, 3.0" << (three ? ", 0.6" : "")
    << "]\nperiodic = [\"x\"" << (three ? ", \"z\"" : "") << "]\n"
    << "[[shape]]\nname = \"floor\"\ntype = \"box\"\nlower = [-1.0, -0.5" << (three ? ", -1.0" : "")
    << "]\nupper = [5.0, 0.0" << (three ? ", 1.6" : "") << "]\n"
    << "[[shape]]\nname = \"column\"\ntype = \"box\"\nlower = [1.4, 0.0" << (three ? ", 0.0" : "")
    << "]\nupper = [2.6, 1.2" << (three ? ", 0.6" : "") << "]\n"
    << "[[body]]\nname = \"floor\"\nkind = \"wall\"\nshape = \"floor\"\n"
    << "[[body]]\nname = \"water\"\nkind = \"fluid\"\nshape = \"column\"\n"
    << "[fluid]\ndensity = 1.0\nreference_velocity = 2.0\nsound_speed = 20.0\n"
    << "[physics]\ngravity = [0.0, -1.0" << (three ? ", 0.0" : "") << "]\n"
    << "[time]\nend = 100.0\noutput_interval = 100.0\n"
    << "[[probe]]\nname = \"face\"\nposition = [0.05, 0.05" << (three ? ", 0.3" : "") << "]\n"
    << "[[gauge]]\nname = \"face\"\nposition = [0.05, 0.0" << (three ? ", 0.05" : "") << "]\nbottom = 0.0\ntop = 1.5\n"
    << "[[gauge]]\nname = \"column\"\nposition = [2.0, 0.0" << (three ? ", 0.3" : "") << "]\nbottom = 0.0\ntop = 1.5\n"
    << "[[velocity_probe]]\nname = \"face\"\nposition = [3.97, 0.1" << (three ? ", 0.58" : "") << "]\n";
  CaseDescription c = parse_case(t.str(), "periodic_collapse.toml");
  c.neighbor_search = "stored";
  return c;
}

// The whole fluid's state, one row per particle in id order: id, x, v, rho, p.
template <int D>
std::vector<std::vector<double>> rows_of(WeaklyCompressibleSolver<double, D>& s, const comm::Communicator& comm) {
  ParticleSet& set = s.fluid_body().particles();
  const Index n = set.owned_count();
  const auto id = set.ids().to_vector();
  const auto x = s.fluid_body().positions().to_vector();
  const auto v = set.template variable<Vec<double, D>>("Velocity").to_vector();
  const auto rho = set.template variable<double>("Density").to_vector();
  const auto p = set.template variable<double>("Pressure").to_vector();
  constexpr std::size_t width = 1 + 2 * D + 2;
  std::vector<double> local;
  local.reserve(n * width);
  for (Index i = 0; i < n; ++i) {
    local.push_back(double(id[i]));
    for (int a = 0; a < D; ++a) local.push_back(x[i][a]);
    for (int a = 0; a < D; ++a) local.push_back(v[i][a]);
    local.push_back(rho[i]);
    local.push_back(p[i]);
  }
  const std::vector<double> all = comm.allgatherv(std::span<const double>(local));
  std::vector<std::vector<double>> rows;
  for (std::size_t k = 0; k < all.size(); k += width) rows.emplace_back(all.begin() + k, all.begin() + k + width);
  std::sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a[0] < b[0]; });
  return rows;
}

// Largest difference of columns [first, first + count) relative to their largest magnitude.
double relative_difference(const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& b,
                           std::size_t first, std::size_t count) {
  double scale = 0, worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t k = first; k < first + count; ++k) {
      scale = std::max(scale, std::abs(b[i][k]));
      worst = std::max(worst, std::abs(a[i][k] - b[i][k]));
    }
  return scale > 0 ? worst / scale : worst;
}

// How many values of columns [1, width) differ in their bits (-0 from +0, any NaN from any other).
std::size_t differing_bits(const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& b) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t k = 1; k < a[i].size(); ++k)
      n += std::bit_cast<std::uint64_t>(a[i][k]) != std::bit_cast<std::uint64_t>(b[i][k]);
  return n;
}

// Waits for every rank with a sleep between polls. While rank 0 runs the case again on one rank,
// the others would otherwise spin in the next test's first collective; four ranks oversubscribed
// on CI's two cores then leave rank 0 a fraction of a core (measured there: np4 near its 300 s
// limit).
void wait_for_all_ranks(const comm::Communicator& comm) {
  if (comm.size() < 2) return;
  MPI_Comm c = *static_cast<const MPI_Comm*>(comm.native_handle());
  MPI_Request request;
  MPI_Ibarrier(c, &request);
  int done = 0;
  for (MPI_Test(&request, &done, MPI_STATUS_IGNORE); !done; MPI_Test(&request, &done, MPI_STATUS_IGNORE))
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
}

// `search`: "stored" (the shared case's) or "direct" (the device default: every pass searches
// the cells anew and reads the neighbours' records, in cell order on one rank, by the runs of
// the id-ordered list on several).
// `shifting`: fluid.particle_shifting (the neighbours' records of ghosts and images after the move).
template <int D>
void compare_with_one_rank(const comm::Communicator& comm, PolicyKind kind, int steps, const char* search,
                           bool periodic, double shifting);

template <int D>
void agrees_with_one_rank(PolicyKind kind, int steps, const char* search = "stored", bool periodic = false,
                          double shifting = 0) {
  const comm::Communicator comm = comm::Communicator::world();
  compare_with_one_rank<D>(comm, kind, steps, search, periodic, shifting);
  wait_for_all_ranks(comm);  // every rank, whatever rank 0's checks returned from
}

template <int D>
void compare_with_one_rank(const comm::Communicator& comm, PolicyKind kind, int steps, const char* search,
                           bool periodic, double shifting) {
  CaseDescription c = periodic ? periodic_collapse(D) : small_dam_break(D);
  c.neighbor_search = search;
  c.particle_shifting = shifting;
  WeaklyCompressibleSolver<double, D> many(c, kind, comm);
  for (int k = 0; k < steps; ++k) many.advance(c.end_time);
  const ObserverSample seen = many.observe();
  const auto rows = rows_of<D>(many, comm);
  const std::uint64_t migrated = comm.allreduce_sum(many.particles_migrated());
  const std::uint64_t owned = many.fluid_count_all_ranks();
  const bool in_shares = many.made_in_shares();
  if (comm.rank() != 0) return;
  // The dam break (a tank case) is made in shares on several ranks, each rank its own
  // particles; the periodic collapse (the general form) whole on every rank.
  if (comm.size() > 1) EXPECT_EQ(in_shares, !periodic);

  WeaklyCompressibleSolver<double, D> one(c, kind);
  for (int k = 0; k < steps; ++k) one.advance(c.end_time);
  const ObserverSample expected = one.observe();
  const auto reference = rows_of<D>(one, comm::Communicator::serial());
  ASSERT_EQ(rows.size(), reference.size());
  ASSERT_EQ(owned, reference.size());
  for (std::size_t i = 0; i < rows.size(); ++i) ASSERT_EQ(rows[i][0], reference[i][0]) << "the ids differ";
  EXPECT_EQ(many.time(), one.time());
  EXPECT_EQ(many.acoustic_steps(), one.acoustic_steps());

  const double dx = relative_difference(rows, reference, 1, D);
  const double dv = relative_difference(rows, reference, 1 + D, D);
  const double drho = relative_difference(rows, reference, 1 + 2 * D, 1);
  const double dp = relative_difference(rows, reference, 2 + 2 * D, 1);
  const double dk = std::abs(seen.kinetic_energy - expected.kinetic_energy) / expected.kinetic_energy;
  const double dprobe = std::abs(seen.probe_pressure[0] - expected.probe_pressure[0]);
  const std::size_t differing = differing_bits(rows, reference);
  std::printf("%dD, %s search, %d ranks, %d advection steps (t = %.4f, %llu acoustic), %zu fluid particles, %llu migrations, "
              "%llu rebalances: relative differences x %.3g, v %.3g, rho %.3g, p %.3g (%zu of %zu values differ in "
              "their bits); kinetic energy %.3g; mass %.17g against %.17g; front %.17g against %.17g; probe %.6g "
              "against %.6g; gauges %.17g, %.17g against %.17g, %.17g\n",
              D, search, comm.size(), steps, one.time(), (unsigned long long)one.acoustic_steps(), rows.size(),
              (unsigned long long)migrated, (unsigned long long)many.rebalances(), dx, dv, drho, dp, differing,
              rows.size() * (2 * D + 2), dk, seen.mass, expected.mass, seen.front, expected.front,
              seen.probe_pressure[0], expected.probe_pressure[0], seen.gauge_elevation.at(0), seen.gauge_elevation.at(1),
              expected.gauge_elevation.at(0), expected.gauge_elevation.at(1));
  if (comm.size() > 1) {
    EXPECT_GT(migrated, 0u) << "the water never crossed a subdomain";
  }
  // Any number of ranks gives the bits of one rank, on every policy (measured on 1, 2 and 4
  // H100s, docs/multi_gpu.md): x, v, rho, p of every particle, and the front (a max; the
  // probe's sums and the energies are grouped by rank).
  EXPECT_EQ(differing, 0u) << "the particle states differ in their bits from the run on one rank";
  EXPECT_EQ(seen.front, expected.front);
  if (periodic) {
    // The water went through the faces: particles at both ends of the domain along x.
    double lowest = 1e300, highest = -1e300;
    for (const auto& r : rows) lowest = std::min(lowest, r[1]), highest = std::max(highest, r[1]);
    std::printf("  periodic: fluid from x = %.3f to %.3f in [0, 4]\n", lowest, highest);
    EXPECT_LT(lowest, 0.2);
    EXPECT_GT(highest, 3.8);
  }
  // The gauges and the velocity probe, read by each point's owner: the bits of one rank.
  ASSERT_EQ(seen.gauge_elevation.size(), 2u);
  ASSERT_EQ(seen.probe_velocity.size(), std::size_t(D));
  for (std::size_t g = 0; g < 2; ++g)
    EXPECT_EQ(std::bit_cast<std::uint64_t>(seen.gauge_elevation[g]), std::bit_cast<std::uint64_t>(expected.gauge_elevation[g]))
        << "gauge " << g << ": " << seen.gauge_elevation[g] << " against " << expected.gauge_elevation[g];
  for (int a = 0; a < D; ++a)
    EXPECT_EQ(std::bit_cast<std::uint64_t>(seen.probe_velocity[a]), std::bit_cast<std::uint64_t>(expected.probe_velocity[a]))
        << "velocity probe, component " << a;
  EXPECT_LE(dx, 1e-9);
  EXPECT_LE(dv, 1e-9);
  EXPECT_LE(drho, 1e-9);
  EXPECT_LE(dp, 1e-9);
  EXPECT_LE(dk, 1e-9);
  EXPECT_LE(std::abs(seen.mass - expected.mass), 1e-12 * expected.mass);
  EXPECT_LE(std::abs(seen.front - expected.front), 1e-9 * expected.front);
  EXPECT_LE(dprobe, 1e-9);
}

// UNISPH_HALO_OVERLAP=1 within a test: the ghosts' refreshes in the acoustic steps split around the
// interior particles' passes (RankShare::overlap_refreshes) on every policy; by default only
// transports whose exchange runs beside the device's work (NCCL) split them.
struct OverlappedRefreshes {
  OverlappedRefreshes() { setenv("UNISPH_HALO_OVERLAP", "1", 1); }
  ~OverlappedRefreshes() { unsetenv("UNISPH_HALO_OVERLAP"); }
};

UNISPH_POLICY_TEST_SUITE(SolverRanks);

TYPED_TEST(SolverRanks, DamBreak2DAgreesWithOneRank) { agrees_with_one_rank<2>(kind_of<TypeParam>(), 200); }
TYPED_TEST(SolverRanks, DamBreak3DAgreesWithOneRank) { agrees_with_one_rank<3>(kind_of<TypeParam>(), 200); }
// Cut by recursive bisection (UNISPH_DECOMPOSITION) instead of the Morton curve: the same bits.
TYPED_TEST(SolverRanks, DamBreak2DBisectionAgreesWithOneRank) {
  setenv("UNISPH_DECOMPOSITION", "bisection", 1);
  agrees_with_one_rank<2>(kind_of<TypeParam>(), 200);
  unsetenv("UNISPH_DECOMPOSITION");
}
TYPED_TEST(SolverRanks, DamBreak2DDirectSearchAgreesWithOneRank) {
  const OverlappedRefreshes overlapped;
  agrees_with_one_rank<2>(kind_of<TypeParam>(), 200, "direct");
}
TYPED_TEST(SolverRanks, DamBreak3DDirectSearchAgreesWithOneRank) {
  agrees_with_one_rank<3>(kind_of<TypeParam>(), 200, "direct");
}
// Periodic axes: the halo holds the images across the faces (the own rank's among them).
TYPED_TEST(SolverRanks, PeriodicCollapse2DAgreesWithOneRank) {
  const OverlappedRefreshes overlapped;
  agrees_with_one_rank<2>(kind_of<TypeParam>(), 200, "stored", true);
}
TYPED_TEST(SolverRanks, PeriodicCollapse3DDirectSearchAgreesWithOneRank) {
  const OverlappedRefreshes overlapped;
  agrees_with_one_rank<3>(kind_of<TypeParam>(), 200, "direct", true);
}
// Particle shifting: the shift reads the ghosts' and images' records, and moves them after.
TYPED_TEST(SolverRanks, DamBreak2DParticleShiftingAgreesWithOneRank) {
  agrees_with_one_rank<2>(kind_of<TypeParam>(), 200, "direct", false, 0.4);
}
TYPED_TEST(SolverRanks, PeriodicCollapse2DParticleShiftingAgreesWithOneRank) {
  agrees_with_one_rank<2>(kind_of<TypeParam>(), 200, "stored", true, 0.4);
}

}  // namespace
