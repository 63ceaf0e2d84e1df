// Obstacles from particle files (sph/obstacle_particles.hpp) and the .vtp reader under them
// (io/vtk_xml_reader.hpp):
//  * the reader gives back exactly what io/vtk_xml_writer.hpp wrote, and refuses broken files
//    with one line naming the file and what is wrong;
//  * a case with an obstacle (a disc of particles with its exact signed distance and normals,
//    written as `unisph generate` writes them) is checked against dx, dimension and tank;
//  * on every policy, a short dam break through the disc: the lattice points it covers are
//    removed, the total mass stays exactly the same, no fluid particle gets into the disc
//    (exact distance, bound stated), the disc's particles do not move, and a checkpoint taken
//    with the obstacle continues bit for bit on seq and par.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <unistd.h>
#include <vector>

#include "support/policy_test.hpp"
#include "support/small_dam_break.hpp"
#include "unisph/io/checkpoint_file.hpp"
#include "unisph/io/vtk_xml_reader.hpp"
#include "unisph/io/vtk_xml_writer.hpp"
#include "unisph/solver/case_file.hpp"
#include "unisph/solver/solver_checkpoint.hpp"
#include "unisph/solver/weakly_compressible_solver.hpp"

using namespace unisph;
using namespace unisph::sph;
namespace fs = std::filesystem;

namespace {

// A folder of its own per process (ctest runs the policies in parallel).
fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("unisph_obstacle_test_" + std::to_string(getpid()));
  fs::create_directories(dir);
  return dir / name;
}

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}
void write_bytes(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

std::string read_error(const fs::path& p) {
  try {
    io::read_vtp(p);
  } catch (const io::VtkReadError& e) {
    return e.what();
  }
  return "";
}

// The disc of radius R centred at c as `unisph generate` would describe it: lattice points of
// spacing dx inside it, with the exact signed distance (NormalDistance), the outward normal and
// the volume dx^2, and the field data Spacing, Dimension, Inside.
struct Disc {
  double cx, cy, radius;
  double distance(double x, double y) const { return std::hypot(x - cx, y - cy) - radius; }
};

void write_disc(const fs::path& path, const Disc& disc, double dx, double file_dx, std::int64_t dimension = 2,
                bool with_normal = true) {
  std::vector<double> points, volume, phi, normal;
  const long n = long(std::ceil(disc.radius / dx)) + 1;
  for (long j = -n; j < n; ++j)
    for (long i = -n; i < n; ++i) {
      const double x = disc.cx + (double(i) + 0.5) * dx, y = disc.cy + (double(j) + 0.5) * dx;
      const double d = disc.distance(x, y);
      if (d >= 0) continue;
      const double r = std::hypot(x - disc.cx, y - disc.cy);
      points.insert(points.end(), {x, y, 0.0});
      volume.push_back(dx * dx);
      phi.push_back(d);
      normal.insert(normal.end(), {(x - disc.cx) / r, (y - disc.cy) / r, 0.0});
    }
  std::vector<io::PointArray> arrays = {io::PointArray::from("Volume", 1, volume),
                                        io::PointArray::from("NormalDistance", 1, phi)};
  if (with_normal) arrays.push_back(io::PointArray::from("Normal", 3, normal));
  io::write_vtp(path, points, arrays,
                {io::PointArray::from("Spacing", 1, std::vector<double>{file_dx}),
                 io::PointArray::from("Dimension", 1, std::vector<std::int64_t>{dimension}),
                 io::PointArray::from("Inside", 1, std::vector<std::int64_t>{1})});
}

// A ball of radius R centred at c in 3D, written the same way.
void write_ball(const fs::path& path, const Vec<double, 3>& c, double radius, double dx) {
  std::vector<double> points, volume, phi, normal;
  const long n = long(std::ceil(radius / dx)) + 1;
  for (long k = -n; k < n; ++k)
    for (long j = -n; j < n; ++j)
      for (long i = -n; i < n; ++i) {
        const Vec<double, 3> x{{c[0] + (double(i) + 0.5) * dx, c[1] + (double(j) + 0.5) * dx, c[2] + (double(k) + 0.5) * dx}};
        const double r = norm(x - c);
        if (r >= radius) continue;
        points.insert(points.end(), {x[0], x[1], x[2]});
        volume.push_back(dx * dx * dx);
        phi.push_back(r - radius);
        normal.insert(normal.end(), {(x[0] - c[0]) / r, (x[1] - c[1]) / r, (x[2] - c[2]) / r});
      }
  io::write_vtp(path, points,
                {io::PointArray::from("Volume", 1, volume), io::PointArray::from("NormalDistance", 1, phi),
                 io::PointArray::from("Normal", 3, normal)},
                {io::PointArray::from("Spacing", 1, std::vector<double>{dx}),
                 io::PointArray::from("Dimension", 1, std::vector<std::int64_t>{3}),
                 io::PointArray::from("Inside", 1, std::vector<std::int64_t>{1})});
}

CaseDescription small_dam_break() {
  CaseDescription c = unisph::testing::small_dam_break();
  c.name = "obstacle_dam_break";
  c.source = "obstacle_case.toml";
  c.probes.clear();
  c.continuity_dissipation = true;
  return c;
}

// The disc stands in the column, so the lattice loses the points it covers and the water
// collapses around and over it.
const Disc disc{1.5, 0.45, 0.3};

CaseDescription case_with_disc(const std::string& file_name) {
  CaseDescription c = small_dam_break();
  const fs::path file = scratch(file_name);
  if (!fs::exists(file)) write_disc(file, disc, c.dx, c.dx);
  c.obstacles.push_back({file.string(), {0.0, 0.0}, 12});
  return c;
}

std::string case_error(const CaseDescription& c) {
  try {
    WeaklyCompressibleSolver<double, 2> solver(c, PolicyKind::seq);
  } catch (const CaseFileError& e) {
    return e.what();
  }
  return "";
}

PolicyKind kind_of_policy(MemorySpace space, bool sequenced) {
  return space == MemorySpace::device ? PolicyKind::device : sequenced ? PolicyKind::seq : PolicyKind::par;
}

}  // namespace

TEST(HostVtkReader, ReadsBackExactlyWhatTheWriterWrote) {
  const std::vector<double> points = {0.1, -2.5, 0.0, 1e-300, 3.25, 7.0, -0.0, 1e300, 2.0};
  const std::vector<float> f32 = {1.5f, -0.25f, 3e-38f};
  const std::vector<double> f64 = {0.1, 0.2, 0.3, -1e-9, 5.0, 6.0};
  const std::vector<std::uint64_t> u64 = {0, 1, (std::uint64_t(1) << 52) + 1};
  const std::vector<std::int64_t> i64 = {-7, 0, 42};
  const fs::path file = scratch("round_trip.vtp");
  io::write_vtp(file, points,
                {io::PointArray::from("F32", 1, f32), io::PointArray::from("F64", 2, f64),
                 io::PointArray::from("U64", 1, u64), io::PointArray::from("I64", 1, i64)},
                {io::PointArray::from("Spacing", 1, std::vector<double>{0.025})});
  const io::PolyDataFile read = io::read_vtp(file);
  EXPECT_EQ(read.points, 3u);
  EXPECT_EQ(read.coordinates, points);
  EXPECT_EQ(read.field_value("Spacing"), 0.025);
  const auto as_doubles = [](const auto& v) { return std::vector<double>(v.begin(), v.end()); };
  EXPECT_EQ(read.point_array("F32", 1).values, as_doubles(f32));
  EXPECT_EQ(read.point_array("F32", 1).vtk_type, "Float32");
  EXPECT_EQ(read.point_array("F64", 2).values, f64);
  EXPECT_EQ(read.point_array("U64", 1).values, as_doubles(u64));
  EXPECT_EQ(read.point_array("I64", 1).values, as_doubles(i64));
  // Float32 points too (the solver's float output).
  const fs::path single = scratch("round_trip_float.vtp");
  io::write_vtp(single, std::vector<float>{1.5f, 2.5f, 0.0f}, {});
  EXPECT_EQ(io::read_vtp(single).coordinates, (std::vector<double>{1.5, 2.5, 0.0}));
}

TEST(HostVtkReader, BrokenFilesAreRefusedWithOneLine) {
  const fs::path good = scratch("good.vtp");
  io::write_vtp(good, std::vector<double>{0.5, 0.5, 0.0, 1.5, 0.5, 0.0},
                {io::PointArray::from("Volume", 1, std::vector<double>{1.0, 1.0})});
  const std::string bytes = read_bytes(good);
  const auto variant = [&](const std::string& name, const std::string& content) {
    write_bytes(scratch(name), content);
    return scratch(name);
  };
  const auto replaced = [&](std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
  };
  std::string nan_bytes = bytes;
  {  // the first Volume value (the first block after the '_' marker) becomes NaN
    const std::size_t at = nan_bytes.find("encoding=\"raw\">\n_") + 17 + 8;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::memcpy(nan_bytes.data() + at, &nan, 8);
  }
  const std::vector<std::pair<fs::path, std::string>> cases = {
      {scratch("missing.vtp"), "missing.vtp: cannot open the file"},
      {variant("text.vtp", "[case]\nname = \"x\"\n"), "text.vtp: is not a VTK XML file"},
      {variant("grid.vtp", replaced(bytes, "type=\"PolyData\"", "type=\"ImageData\"")),
       "grid.vtp: is a VTK 'ImageData' file, not PolyData"},
      {variant("truncated.vtp", bytes.substr(0, bytes.size() - 60)), "truncated.vtp: is truncated"},
      {variant("header_only.vtp", bytes.substr(0, bytes.find("<AppendedData"))), "header_only.vtp: has no <AppendedData>"},
      {variant("ascii.vtp", replaced(bytes, "format=\"appended\"", "format=\"ascii\"")),
       "ascii.vtp: array 'Volume' (in <PointData>) has format \"ascii\""},
      {variant("count.vtp", replaced(bytes, "NumberOfPoints=\"2\"", "NumberOfPoints=\"3\"")),
       "count.vtp: array 'Volume' holds 16 bytes where 3 tuples of 1 Float64 take 24"},
      {variant("nan.vtp", nan_bytes), "nan.vtp: array 'Volume': the value of tuple 0 (component 0) is not finite"},
  };
  for (const auto& [file, expected] : cases) {
    const std::string message = read_error(file);
    EXPECT_NE(message.find(expected), std::string::npos) << "message: " << message << "\nexpected: " << expected;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  const io::PolyDataFile read = io::read_vtp(good);
  try {
    read.point_array("Normal", 3);
    ADD_FAILURE() << "a missing array must be an error";
  } catch (const io::VtkReadError& e) {
    EXPECT_NE(std::string(e.what()).find("good.vtp: has no point array 'Normal'"), std::string::npos) << e.what();
  }
}

TEST(HostSphObstacle, CaseFileNamesObstaclesRelativeToItself) {
  const std::string text = R"([case]
name = "t"
[geometry]
dx = 0.1
tank = [2.0, 1.5]
column = [1.0, 0.5]
[fluid]
density = 1.0
reference_velocity = 2.0
sound_speed = 20.0
[physics]
gravity = 1.0
[time]
end = 0.5
[[obstacle]]
file = "bodies/block.vtp"
translation = [0.5, 0.25]
[[obstacle]]
file = "/abs/disc.vtp"
)";
  const CaseDescription c = parse_case(text, "cases/x/case.toml");
  ASSERT_EQ(c.obstacles.size(), 2u);
  EXPECT_EQ(c.obstacles[0].file, "cases/x/bodies/block.vtp");
  EXPECT_EQ(c.obstacles[0].translation, (std::vector<double>{0.5, 0.25}));
  EXPECT_EQ(c.obstacles[0].line, 16);
  EXPECT_EQ(c.obstacles[1].file, "/abs/disc.vtp");
  EXPECT_EQ(c.obstacles[1].translation, (std::vector<double>{0.0, 0.0}));
  const auto error = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    t.replace(t.find(from), from.size(), to);
    try {
      parse_case(t, "case.toml");
    } catch (const CaseFileError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("translation = [0.5, 0.25]", "rotation = 1").find("case.toml:17: key 'obstacle.rotation': unknown key"),
            std::string::npos);
  EXPECT_NE(error("translation = [0.5, 0.25]", "translation = [0.5]").find("case.toml:17: key 'obstacle.translation': must have 2"),
            std::string::npos);
  EXPECT_NE(error("file = \"bodies/block.vtp\"", "file = 3").find("case.toml:16: key 'obstacle.file': must be a string"),
            std::string::npos);
  EXPECT_NE(error("file = \"bodies/block.vtp\"", "name = \"b\"").find("key 'obstacle.name': unknown key"), std::string::npos);
  EXPECT_NE(error("file = \"/abs/disc.vtp\"", "").find("key 'obstacle.file': missing value"), std::string::npos);
}

TEST(HostSphObstacle, BadObstaclesAreRefusedWithOneLineNamingCaseLineAndFile) {
  CaseDescription c = small_dam_break();
  write_disc(scratch("coarse.vtp"), disc, 0.1, 0.1);
  write_disc(scratch("three_d.vtp"), disc, 0.05, 0.05, 3);
  write_disc(scratch("no_normal.vtp"), disc, 0.05, 0.05, 2, false);
  write_disc(scratch("disc.vtp"), disc, 0.05, 0.05);
  const std::vector<std::pair<ObstacleDescription, std::string>> cases = {
      {{scratch("coarse.vtp").string(), {0.0, 0.0}, 12}, "coarse.vtp: was generated with dx = 0.1; the case's dx is 0.05"},
      {{scratch("three_d.vtp").string(), {0.0, 0.0}, 12}, "three_d.vtp: is a 3D particle set; the case is 2D"},
      {{scratch("no_normal.vtp").string(), {0.0, 0.0}, 12}, "no_normal.vtp: has no point array 'Normal'"},
      {{scratch("absent.vtp").string(), {0.0, 0.0}, 12}, "absent.vtp: cannot open the file"},
      {{scratch("disc.vtp").string(), {-1.3, 0.0}, 12}, "lies outside the tank [0, 5.366] x [0, 5.366]"},
  };
  for (const auto& [obstacle, expected] : cases) {
    c.obstacles = {obstacle};
    const std::string message = case_error(c);
    EXPECT_EQ(message.rfind("obstacle_case.toml:12: key 'obstacle.file': ", 0), 0u) << message;
    EXPECT_NE(message.find(expected), std::string::npos) << "message: " << message << "\nexpected: " << expected;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

UNISPH_POLICY_TEST_SUITE(SphObstacle);

TYPED_TEST(SphObstacle, DamBreakFlowsAroundTheObstacle) {
  const PolicyKind kind = kind_of_policy(TypeParam::space, std::is_same_v<TypeParam, SequencedPolicy>);
  const CaseDescription plain = small_dam_break();
  const CaseDescription c = case_with_disc("flow_disc.vtp");
  WeaklyCompressibleSolver<double, 2> without(plain, PolicyKind::seq);
  WeaklyCompressibleSolver<double, 2> solver(c, kind);
  const double dx = c.dx;
  // The disc's wall: its particles with phi >= -4 dx, after the tank's.
  ASSERT_EQ(solver.obstacle_wall_counts().size(), 1u);
  const Index disc_wall = solver.obstacle_wall_counts()[0];
  EXPECT_EQ(solver.wall_count(), without.wall_count() + disc_wall);
  Index disc_layers = 0;  // the disc's particles (write_disc) within 4 dx of its surface
  for (long j = -7; j < 7; ++j)
    for (long i = -7; i < 7; ++i) {
      const double d = disc.distance(disc.cx + (i + 0.5) * dx, disc.cy + (j + 0.5) * dx);
      disc_layers += d < 0 && d >= -4 * dx;
    }
  EXPECT_EQ(disc_wall, disc_layers);
  EXPECT_EQ(solver.fluid_count() + solver.removed_fluid_count(), without.fluid_count());
  // Every lattice point within dx/2 of the disc or in it is gone; the estimate from the nearest
  // disc particle (phi_w + n_w . (x - x_w), never above the exact distance for a disc) may take
  // a few more, none beyond 0.6 dx.
  Index within_half = 0, within_06 = 0;
  for (long j = 0; j < 20; ++j)
    for (long i = 0; i < 40; ++i) {
      const double d = disc.distance((i + 0.5) * dx, (j + 0.5) * dx);
      within_half += d < 0.5 * dx;
      within_06 += d < 0.6 * dx;
    }
  EXPECT_GE(solver.removed_fluid_count(), within_half);
  EXPECT_LE(solver.removed_fluid_count(), within_06);
  for (const Vec<double, 2>& x : solver.fluid_body().positions().to_vector())
    EXPECT_GE(disc.distance(x[0], x[1]), 0.5 * dx);

  const auto by_id = [](Body<double, 2>& body) {
    const auto x = body.positions().to_vector();
    const auto id = body.particles().ids().to_vector();
    std::vector<Vec<double, 2>> out(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) out[id[i] - body.particles().first_id()] = x[i];
    return out;
  };
  const auto wall0 = by_id(solver.wall_body());
  const double mass0 = solver.observe().mass;
  while (solver.acoustic_steps() < 400) solver.advance(1e9);
  const ObserverSample s = solver.observe();
  EXPECT_EQ(s.mass, mass0) << "the mass of every particle is fixed";
  EXPECT_GT(s.kinetic_energy, 0.0);
  EXPECT_EQ(by_id(solver.wall_body()), wall0) << "wall and obstacle particles never move";
  double deepest = std::numeric_limits<double>::infinity();
  for (const Vec<double, 2>& x : solver.fluid_body().positions().to_vector())
    deepest = std::min(deepest, disc.distance(x[0], x[1]));
  std::printf("[ measured ] %s: after %llu acoustic steps (t = %.3f) the fluid particle nearest the disc's centre is "
              "%.3f dx from its surface (bound: no particle deeper inside than 0.25 dx); %u lattice points removed, "
              "%u disc wall particles\n",
              std::string(TypeParam::test_label).c_str(), (unsigned long long)solver.acoustic_steps(), solver.time(),
              deepest / dx, unsigned(solver.removed_fluid_count()), unsigned(disc_wall));
  EXPECT_GT(deepest, -0.25 * dx);
}

TYPED_TEST(SphObstacle, CheckpointWithObstacleContinuesBitForBit) {
  const PolicyKind kind = kind_of_policy(TypeParam::space, std::is_same_v<TypeParam, SequencedPolicy>);
  const CaseDescription c = case_with_disc("checkpoint_disc.vtp");
  WeaklyCompressibleSolver<double, 2> straight(c, kind);
  WeaklyCompressibleSolver<double, 2> first(c, kind);
  for (int k = 0; k < 10; ++k) straight.advance(1e9), first.advance(1e9);
  const fs::path file = scratch(std::string("obstacle_") + std::string(TypeParam::test_label) + ".bin");
  first.write_checkpoint(file, "state");
  for (int k = 0; k < 10; ++k) straight.advance(1e9);
  WeaklyCompressibleSolver<double, 2> restored(c, kind);
  EXPECT_EQ(restored.restore_checkpoint(file), "state");
  for (int k = 0; k < 10; ++k) restored.advance(1e9);
  EXPECT_EQ(restored.time(), straight.time());
  EXPECT_EQ(restored.acoustic_steps(), straight.acoustic_steps());
  const auto x = straight.fluid_body().positions().to_vector(), y = restored.fluid_body().positions().to_vector();
  ASSERT_EQ(x.size(), y.size());
  double worst = 0;
  for (std::size_t i = 0; i < x.size(); ++i) worst = std::max(worst, norm(x[i] - y[i]));
  if (TypeParam::space == MemorySpace::host)
    EXPECT_EQ(worst, 0.0) << "a restart continues bit for bit on the CPU";
  else
    EXPECT_LE(worst, 1e-9 * 5.366);
  EXPECT_EQ(restored.wall_body().positions().to_vector(), straight.wall_body().positions().to_vector());
  // A checkpoint of the case without the obstacle is refused by the case with it.
  WeaklyCompressibleSolver<double, 2> other(small_dam_break(), kind);
  try {
    other.restore_checkpoint(file);
    ADD_FAILURE() << "a checkpoint of another case must be refused";
  } catch (const io::CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("number of obstacles (0 here, 1 in the checkpoint)"), std::string::npos)
        << e.what();
  }
}

// 3D, float: a ball in the column of a narrow 3D dam break (dx = 0.1, 1,000 lattice points).
TYPED_TEST(SphObstacle, BallInA3DDamBreakInFloat) {
  const PolicyKind kind = kind_of_policy(TypeParam::space, std::is_same_v<TypeParam, SequencedPolicy>);
  CaseDescription c = small_dam_break();
  c.dimension = 3;
  c.dx = 0.1;
  c.tank = {5.366, 2.0, 0.5};
  c.column = {2.0, 1.0, 0.5};
  const Vec<double, 3> centre{{1.5, 0.45, 0.25}};
  const double radius = 0.2;
  const fs::path file = scratch("ball.vtp");
  write_ball(file, centre, radius, c.dx);
  WeaklyCompressibleSolver<float, 3> without(c, kind);
  c.obstacles.push_back({file.string(), {0.0, 0.0, 0.0}, 20});
  WeaklyCompressibleSolver<float, 3> solver(c, kind);
  ASSERT_EQ(solver.obstacle_wall_counts().size(), 1u);
  EXPECT_EQ(solver.wall_count(), without.wall_count() + solver.obstacle_wall_counts()[0]);
  EXPECT_EQ(solver.fluid_count() + solver.removed_fluid_count(), without.fluid_count());
  EXPECT_GT(solver.removed_fluid_count(), 0u);
  const auto wall0 = solver.wall_body().positions().to_vector();
  const double mass0 = solver.observe().mass;
  while (solver.acoustic_steps() < 150) solver.advance(1e9);
  EXPECT_EQ(solver.observe().mass, mass0);
  EXPECT_EQ(solver.wall_body().positions().to_vector(), wall0) << "wall and obstacle particles never move";
  double deepest = std::numeric_limits<double>::infinity();
  for (const Vec<float, 3>& x : solver.fluid_body().positions().to_vector())
    deepest = std::min(deepest, norm(Vec<double, 3>{{double(x[0]), double(x[1]), double(x[2])}} - centre) - radius);
  std::printf("[ measured ] %s, 3D float: after %llu acoustic steps the fluid particle nearest the ball's centre is "
              "%.3f dx from its surface (bound: none deeper inside than 0.25 dx); %u lattice points removed, %u ball "
              "wall particles\n",
              std::string(TypeParam::test_label).c_str(), (unsigned long long)solver.acoustic_steps(), deepest / c.dx,
              unsigned(solver.removed_fluid_count()), unsigned(solver.obstacle_wall_counts()[0]));
  EXPECT_GT(deepest, -0.25 * c.dx);
}

TEST(HostSphObstacle, OlderCheckpointVersionsAreRefused) {
  const fs::path file = scratch("version2.bin");
  io::CheckpointWriter out(2);
  out.section("run");
  out.commit(file);
  try {
    read_checkpoint_summary(file);
    ADD_FAILURE() << "a version 2 checkpoint must be refused";
  } catch (const io::CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("has format version 2; this unisph reads version " + std::to_string(solver_checkpoint_version)), std::string::npos)
        << e.what();
  }
}
