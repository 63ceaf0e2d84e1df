// Checkpoint and restart of the SPH solver: a run of N advection steps straight against N/2,
// a checkpoint, a fresh solver restored from it and N/2 more (bit for bit on seq; on par and
// the GPU the figure is printed and bounded by round-off), and checkpoints that must be refused
// (truncated, damaged, not a checkpoint, another precision, dimension or case), each with one
// line naming the file and what is wrong.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <unistd.h>

#include "support/policy_test.hpp"
#include "support/small_dam_break.hpp"
#include "unisph/io/checkpoint_file.hpp"
#include "unisph/solver/solver_checkpoint.hpp"
#include "unisph/solver/weakly_compressible_solver.hpp"

using namespace unisph;
using namespace unisph::sph;
using unisph::testing::kind_of;
namespace fs = std::filesystem;

namespace {

using unisph::testing::small_dam_break;

// A file name of its own per process and test (ctest runs the policies in parallel).
fs::path scratch_file(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("unisph_checkpoint_test_" + std::to_string(getpid()));
  fs::create_directories(dir);
  return dir / name;
}

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void write_bytes(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
}

// The largest difference between two bodies over every sortable variable, compared element
// by element as floating values (ids as integers), relative to the largest magnitude of that
// variable; 0 means identical bytes (checked separately).
template <class T, int D>
double largest_relative_difference(Body<T, D>& a, Body<T, D>& b, bool& identical_bytes) {
  double worst = 0;
  identical_bytes = true;
  for (const std::string& name : a.particles().variables().sortable_names()) {
    const std::string& type = a.particles().variables().entry(name).type_name;
    if (type == type_name<std::uint64_t>()) {
      const auto x = a.particles().template variable<std::uint64_t>(name).to_vector();
      const auto y = b.particles().template variable<std::uint64_t>(name).to_vector();
      if (x != y) {
        identical_bytes = false;
        worst = 1;  // the particles are in another order
      }
      continue;
    }
    std::vector<T> x, y;
    if (type == type_name<T>()) {
      x = a.particles().template variable<T>(name).to_vector();
      y = b.particles().template variable<T>(name).to_vector();
    } else {
      for (const Vec<T, D>& v : a.particles().template variable<Vec<T, D>>(name).to_vector())
        for (int k = 0; k < D; ++k) x.push_back(v[k]);
      for (const Vec<T, D>& v : b.particles().template variable<Vec<T, D>>(name).to_vector())
        for (int k = 0; k < D; ++k) y.push_back(v[k]);
    }
    EXPECT_EQ(x.size(), y.size()) << name;
    if (std::memcmp(x.data(), y.data(), x.size() * sizeof(T)) != 0) identical_bytes = false;
    double scale = 0, diff = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      scale = std::max(scale, std::abs(double(x[i])));
      diff = std::max(diff, std::abs(double(x[i]) - double(y[i])));
    }
    if (scale > 0) worst = std::max(worst, diff / scale);
  }
  return worst;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const io::CheckpointError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

UNISPH_POLICY_TEST_SUITE(SphCheckpoint);

template <class T, class P>
void check_restart(const char* precision) {
  constexpr int steps = 40;  // advection steps (about 200 acoustic steps at dx = H/20)
  const PolicyKind kind = kind_of<P>();
  const CaseDescription c = small_dam_break();
  WeaklyCompressibleSolver<T, 2> straight(c, kind);
  for (int k = 0; k < steps; ++k) straight.advance(c.end_time);

  const fs::path file = scratch_file(std::string("restart_") + std::string(P::test_label) + "_" + precision + ".bin");
  {
    WeaklyCompressibleSolver<T, 2> first_half(c, kind);
    for (int k = 0; k < steps / 2; ++k) first_half.advance(c.end_time);
    first_half.write_checkpoint(file, "opaque run state");
  }
  EXPECT_FALSE(fs::exists(file.string() + ".tmp")) << "the temporary file is renamed";
  const CheckpointSummary summary = read_checkpoint_summary(file);
  EXPECT_EQ(summary.dimension, 2);
  EXPECT_EQ(summary.precision, precision);
  EXPECT_EQ(summary.advection_steps, std::uint64_t(steps / 2));
  EXPECT_EQ(physics_difference(c, summary.description), "");

  WeaklyCompressibleSolver<T, 2> restarted(summary.description, kind);
  EXPECT_EQ(restarted.restore_checkpoint(file), "opaque run state");
  EXPECT_EQ(restarted.time(), summary.time);
  for (int k = 0; k < steps / 2; ++k) restarted.advance(c.end_time);

  EXPECT_EQ(restarted.advection_steps(), straight.advection_steps());
  EXPECT_EQ(restarted.acoustic_steps(), straight.acoustic_steps());
  bool identical = false;
  const double fluid = largest_relative_difference(straight.fluid_body(), restarted.fluid_body(), identical);
  bool wall_identical = false;
  largest_relative_difference(straight.wall_body(), restarted.wall_body(), wall_identical);
  std::printf("[ measured ] %s %s: %llu acoustic steps straight vs restarted at step %d: fluid variables %s "
              "(largest relative difference %.3e), wall %s; time %s\n",
              std::string(P::test_label).c_str(), precision, (unsigned long long)straight.acoustic_steps(), steps / 2,
              identical ? "bit for bit equal" : "differ", fluid, wall_identical ? "equal" : "differs",
              restarted.time() == straight.time() ? "equal" : "differs");
  EXPECT_TRUE(wall_identical);
  if constexpr (std::is_same_v<P, SequencedPolicy>) {
    EXPECT_TRUE(identical) << "on seq a restarted run continues bit for bit";
    EXPECT_EQ(restarted.time(), straight.time());
  } else {
    // Round-off of the order of a few hundred steps' accumulation (the state is the same; only
    // the order of floating additions may differ between runs on par and the GPU).
    EXPECT_LE(fluid, sizeof(T) == 8 ? 1e-9 : 1e-3);
    EXPECT_NEAR(restarted.time(), straight.time(), 1e-9 * straight.time());
  }
  const ObserverSample a = straight.observe(), b = restarted.observe();
  if constexpr (std::is_same_v<P, SequencedPolicy>) {
    EXPECT_EQ(a.front, b.front);
    EXPECT_EQ(a.probe_pressure, b.probe_pressure);
    EXPECT_EQ(a.kinetic_energy, b.kinetic_energy);
  }
  EXPECT_EQ(a.mass, b.mass);
  fs::remove(file);
  std::error_code ignored;
  fs::remove(file.parent_path(), ignored);  // only when empty (another test may still use it)
}

TYPED_TEST(SphCheckpoint, RestartedRunContinuesToTheSameStateDouble) { check_restart<double, TypeParam>("double"); }
TYPED_TEST(SphCheckpoint, RestartedRunContinuesToTheSameStateFloat) { check_restart<float, TypeParam>("float"); }

TEST(HostSphCheckpoint, BrokenOrForeignCheckpointsAreRefusedWithOneLine) {
  const CaseDescription c = small_dam_break();
  const fs::path good = scratch_file("good.bin");
  {
    WeaklyCompressibleSolver<double, 2> solver(c, PolicyKind::seq);
    for (int k = 0; k < 3; ++k) solver.advance(c.end_time);
    solver.write_checkpoint(good);
  }
  const std::string bytes = read_bytes(good);
  ASSERT_GT(bytes.size(), 1000u);

  auto restore_double_2d = [&](const fs::path& p, const CaseDescription& d = small_dam_break()) {
    return error_of([&] {
      WeaklyCompressibleSolver<double, 2> solver(d, PolicyKind::seq);
      solver.restore_checkpoint(p);
    });
  };
  struct Expectation {
    std::string file;
    std::string message;
    std::string expected;
  };
  std::vector<Expectation> checks;

  for (std::size_t keep : {std::size_t(10), std::size_t(30), bytes.size() / 2, bytes.size() - 1}) {
    const fs::path p = scratch_file("truncated_" + std::to_string(keep) + ".bin");
    write_bytes(p, bytes.substr(0, keep));
    checks.push_back({p.string(), restore_double_2d(p), keep < 30 ? "not a unisph checkpoint" : "truncated"});
    checks.push_back({p.string(), error_of([&] { read_checkpoint_summary(p); }), keep < 30 ? "not a unisph checkpoint" : "truncated"});
  }
  {
    std::string damaged = bytes;
    damaged[bytes.size() / 2] ^= 0x20;
    const fs::path p = scratch_file("damaged.bin");
    write_bytes(p, damaged);
    checks.push_back({p.string(), restore_double_2d(p), "damaged (checksum mismatch)"});
  }
  {
    const fs::path p = scratch_file("not_a_checkpoint.toml");
    write_bytes(p, "[geometry]\ndx = 0.05\n");
    checks.push_back({p.string(), restore_double_2d(p), "is not a unisph checkpoint"});
    checks.push_back({(p.string() + ".missing"), restore_double_2d(p.string() + ".missing"), "cannot be opened"});
  }
  checks.push_back({good.string(), error_of([&] {
                      WeaklyCompressibleSolver<float, 2> solver(c, PolicyKind::seq);
                      solver.restore_checkpoint(good);
                    }),
                    "holds a 2D double run; it cannot continue as a 2D float run"});
  checks.push_back({good.string(), error_of([&] {
                      WeaklyCompressibleSolver<double, 3> solver(small_dam_break(3), PolicyKind::seq);
                      solver.restore_checkpoint(good);
                    }),
                    "holds a 2D double run; it cannot continue as a 3D double run"});
  {
    CaseDescription finer = small_dam_break();
    finer.dx = 0.04;
    checks.push_back({good.string(), restore_double_2d(good, finer),
                      "was written for another case ('small_dam_break'): geometry.dx (0.040000000000000001 here, "
                      "0.050000000000000003 in the checkpoint)"});
  }
  {
    CaseDescription whole_steps = small_dam_break();
    whole_steps.last_acoustic_step = "full";
    checks.push_back({good.string(), restore_double_2d(good, whole_steps),
                      "was written for another case ('small_dam_break'): time.last_acoustic_step (\"full\" here, "
                      "\"shortened\" in the checkpoint)"});
  }
  for (const Expectation& e : checks) {
    EXPECT_NE(e.message.find("checkpoint " + e.file + ": "), std::string::npos) << e.message;
    EXPECT_NE(e.message.find(e.expected), std::string::npos) << e.message << "\nexpected: " << e.expected;
    EXPECT_EQ(e.message.find('\n'), std::string::npos) << e.message;
    std::printf("refused: %s\n", e.message.c_str());
  }
  fs::remove_all(good.parent_path());
}
