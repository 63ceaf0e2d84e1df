// Builds the multi-resolution level set of teapot.stl (9438 triangles) with N data points along
// its longest side (data spacing = longest side / N), on every policy this build has, and prints
// per stage the wall time (each stage ends with a fence), the packages and data points of the
// finest layer and its memory per data point (phi, cell -> package index, package metadata).
//
//   bench_level_set [N ...] [--policy seq|par|device ...] [--sign winding|pseudonormal]
//                   [--no-kernel-integrals] [--no-cleaning] [--repeat R] [--openvdb] [--threads T]
//                   [--half-width W]                                          default N: 256 512
//
// --openvdb (where built with OpenVDB): OpenVDB's meshToLevelSet of the same mesh at the same
// voxel size, half width W voxels (default 3), float, in the same run; its time (mesh in memory,
// no file input or output) and memUsage() per active voxel, beside our finest layer's bytes per
// data point with |phi| < W dx in float (phi 4 bytes, the cell -> package index, package cell,
// type and 27 neighbours). W is at most 4: our finest band holds every point with |phi| < 4 dx
// (the nearest surface point's cell is core, and the point's cell is that cell or its neighbour).
//
// --threads T: at most T host threads (set_host_threads; OpenVDB runs on the same oneTBB, so it
// is held to T as well). --threads 1 compares the work of both on one core.
//
// --sign: the generalized winding number (default; right for teapot.stl, which has walls
// inside its volume) or the pseudonormal of the nearest feature (cheaper; wrong next to those
// walls).
//
// Every line also gives the process's CPU time over the build (all threads; on a shared machine a
// fairer figure than the wall time). The mesh is read and its BVH built once, outside the timings; the GPU is warmed up by one
// small build first. The data folder is the source tree's tests/data, or $UNISPH_TEST_DATA_DIR.
#include <algorithm>
#include <array>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "unisph/exec/algorithms.hpp"
#include "unisph/geometry/mesh_repair.hpp"
#include "unisph/levelset/multi_resolution_level_set.hpp"
#if UNISPH_BENCH_HAS_OPENVDB
#include "levelset/openvdb_mesh_to_level_set.hpp"
#endif

namespace {
using namespace unisph;
using Vec3 = Vec<Real, 3>;

// CPU time of the whole process (every thread), in seconds: on a shared machine a fairer figure
// than the wall time.
double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

std::string data_file(const std::string& relative) {
  const char* dir = std::getenv("UNISPH_TEST_DATA_DIR");
  return std::string(dir ? dir : UNISPH_BENCH_DATA_DIR) + "/" + relative;
}

struct Options {
  bool winding = true;
  bool kernel_integrals = true;
  bool cleaning = true;
  bool openvdb = false;
  int repeat = 1;
  int half_width = 3;  // voxels: OpenVDB's band, and the |phi| < W dx our memory figure counts
};

template <class P>
MultiResolutionLevelSet<3> build(P policy, TriangleMeshSearch& search, const Vec3& lo, const Vec3& hi, Real dx,
                                 const Options& options) {
  if (options.winding)
    return MultiResolutionLevelSet<3>(policy, WindingNumberSign<TriangleMeshSearchView>{search.view(policy)}, lo, hi, dx,
                                      0, options.kernel_integrals, options.cleaning);
  return MultiResolutionLevelSet<3>(policy, search.view(policy), lo, hi, dx, 0, options.kernel_integrals,
                                    options.cleaning);
}

template <class P>
void run(P policy, TriangleMeshSearch& search, const Vec3& lo, const Vec3& hi, int n, const Options& options) {
  Real longest = 0;
  for (int k = 0; k < 3; ++k) longest = std::max(longest, hi[k] - lo[k]);
  const Real dx = longest / Real(n);
  for (int r = 0; r < options.repeat; ++r) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = process_cpu_seconds();
    MultiResolutionLevelSet<3> level_set = build(policy, search, lo, hi, dx, options);
    fence(policy);
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double cpu = process_cpu_seconds() - cpu_start;
    const LevelSetStageTimes& t = level_set.stage_seconds();
    LevelSetLayer<3>& finest = level_set.finest();
    // Our finest layer in float per data point with |phi| < W dx (OpenVDB's half width).
    const std::vector<Real> phi = finest.phi.to_vector();
    std::size_t in_band = 0;
    for (std::size_t i = std::size_t(far_field_packages) * package_points<3>; i < phi.size(); ++i)
      in_band += std::fabs(phi[i]) < Real(options.half_width) * dx;
    const double float_bytes =
        double(finest.packages()) * (package_points<3> * 4.0 + sizeof(std::uint64_t) + sizeof(PackageType) +
                                     sizeof(PackageNeighbourhood<3>)) +
        double(finest.grid().cell_count()) * sizeof(std::uint32_t);
    std::printf(
        "%-6s N=%-5d levels=%d finest: packages=%zu data_points=%zu bytes/point=%.2f points(|phi|<%ddx)=%zu "
        "float bytes/point(|phi|<%ddx)=%.2f removed=%zu | tagging %.3f s, packages %.3f s, distance %.3f s, normals "
        "%.3f s, cleaning %.3f s, kernel integrals %.3f s, total %.3f s (CPU time %.3f s); signed distance "
        "(tagging+packages+distance) %.3f s (%s, %s sign)\n",
        std::string(P::name).c_str(), n, level_set.levels(), finest.data_packages(),
        finest.data_packages() * package_points<3>, finest.bytes_per_data_point(), options.half_width, in_band,
        options.half_width, float_bytes / double(in_band),
        std::size_t(level_set.removed_data_points()), t.tagging, t.packages, t.distance, t.normals, t.cleaning,
        t.kernel_integrals, total, cpu, t.tagging + t.packages + t.distance, sizeof(Real) == 4 ? "float" : "double",
        options.winding ? "winding" : "pseudonormal");
    std::fflush(stdout);
  }
}

}  // namespace

// A whole positive number, or a one-line error naming the argument and exit status 2.
int positive_argument(const std::string& what, const std::string& text) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v <= 0 || v > 1 << 20) {
    std::fprintf(stderr,
                 "bench_level_set: %s '%s' is not a positive whole number (usage: bench_level_set [N ...] [--policy "
                 "seq|par|device ...] [--sign winding|pseudonormal] [--no-kernel-integrals] [--no-cleaning] [--repeat R] "
                 "[--openvdb] [--threads T] [--half-width W])\n",
                 what.c_str(), text.c_str());
    std::exit(2);
  }
  return int(v);
}

int main(int argc, char** argv) {
  std::vector<int> sizes;
  std::vector<PolicyKind> policies;
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--policy" && i + 1 < argc)
      policies.push_back(parse_policy(argv[++i]));
    else if (a == "--repeat" && i + 1 < argc)
      options.repeat = positive_argument("--repeat", argv[++i]);
    else if (a == "--sign" && i + 1 < argc) {
      const std::string sign = argv[++i];
      if (sign != "winding" && sign != "pseudonormal") {
        std::fprintf(stderr, "bench_level_set: --sign '%s' is neither 'winding' nor 'pseudonormal'\n", sign.c_str());
        return 2;
      }
      options.winding = sign == "winding";
    } else if (a == "--no-kernel-integrals")
      options.kernel_integrals = false;
    else if (a == "--no-cleaning")
      options.cleaning = false;
    else if (a == "--openvdb")
      options.openvdb = true;
    else if (a == "--half-width" && i + 1 < argc) {
      options.half_width = positive_argument("--half-width", argv[++i]);
      if (options.half_width > 4) {
        std::fprintf(stderr, "bench_level_set: --half-width %d is wider than our band (every point with |phi| < 4 dx)\n",
                     options.half_width);
        return 2;
      }
    } else if (a == "--threads" && i + 1 < argc)
      set_host_threads(positive_argument("--threads", argv[++i]));
    else
      sizes.push_back(positive_argument("the size N", a));
  }
  if (sizes.empty()) sizes = {256, 512};
  if (policies.empty()) policies = execution_info().available;
  const LoadedMesh loaded = load_triangle_mesh(data_file("geometry/teapot.stl"));
  TriangleMeshSearch search(loaded.mesh);
  Vec3 lo, hi;
  for (int k = 0; k < 3; ++k) lo[k] = Real(loaded.report.box_min[k]), hi[k] = Real(loaded.report.box_max[k]);
  std::printf("teapot.stl: %zu triangles; host threads %d%s%s\n", loaded.mesh.triangles.size(), host_threads(),
              execution_info().device_present ? "; GPU " : "", execution_info().device_name.c_str());
  if (options.openvdb) {
#if UNISPH_BENCH_HAS_OPENVDB
    std::vector<std::array<float, 3>> vertices;
    std::vector<std::array<unsigned, 3>> triangles;
    for (const auto& v : loaded.mesh.vertices) vertices.push_back({float(v[0]), float(v[1]), float(v[2])});
    for (const auto& t : loaded.mesh.triangles) triangles.push_back({t[0], t[1], t[2]});
    Real longest = 0;
    for (int k = 0; k < 3; ++k) longest = std::max(longest, hi[k] - lo[k]);
    for (int n : sizes) {
      const double cpu_start = process_cpu_seconds();
      const auto r = bench::openvdb_mesh_to_level_set(vertices, triangles, float(longest / Real(n)),
                                                      float(options.half_width));
      const double cpu = process_cpu_seconds() - cpu_start;
      std::printf("openvdb N=%-5d meshToLevelSet (float, half width %d voxels) %.3f s (CPU time %.3f s), active voxels "
                  "%zu, memUsage %zu bytes = %.2f bytes/active voxel\n",
                  n, options.half_width, r.seconds, cpu, r.active_voxels, r.memory_bytes, double(r.memory_bytes) / double(r.active_voxels));
      std::fflush(stdout);
    }
#else
    std::printf("openvdb: not built in (CMake did not find OpenVDB)\n");
#endif
  }
  for (PolicyKind kind : policies) {
    require_policy(kind);
    for (int n : sizes) {
      if (kind == PolicyKind::seq) run(seq, search, lo, hi, n, options);
      if (kind == PolicyKind::par) run(par, search, lo, hi, n, options);
#if UNISPH_HAS_CUDA
      if (kind == PolicyKind::device) {
        static bool warm = false;
        if (!warm) {
          build(par_device, search, lo, hi, (hi[0] - lo[0]) / 32, options);
          warm = true;
        }
        run(par_device, search, lo, hi, n, options);
      }
#endif
    }
  }
  return 0;
}
