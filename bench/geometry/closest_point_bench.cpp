// Closest point with sign on the teapot (teapot.stl, 9438 triangles): queries per second on
// every policy this build has. The query points lie within 3 % of the teapot's size (its box
// diagonal) from the surface: a point on a random triangle moved by up to that distance in a
// random direction. Each query finds the nearest triangle through the BVH and signs the
// distance by the angle-weighted pseudonormal: what a level-set build does per grid point.
//
//   ClosestPointWithSign<policy>/N/order   items_per_second = queries/s; label: policy, precision, N,
//                                          triangles, order
// order 0: the points in random order (neighbouring queries far apart: the hard case for a GPU
// warp); order 1: the same points sorted along a Morton curve, as the grid points of a level
// set or the particles of a sorted particle set come.
//
// The data folder is the source tree's tests/data, or $UNISPH_TEST_DATA_DIR where set.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "unisph/exec/algorithms.hpp"
#include "unisph/geometry/mesh_repair.hpp"
#include "unisph/geometry/triangle_mesh_search.hpp"

namespace {
using namespace unisph;
using Vec3 = Vec<Real, 3>;

std::string data_file(const std::string& relative) {
  const char* dir = std::getenv("UNISPH_TEST_DATA_DIR");
  return std::string(dir ? dir : UNISPH_BENCH_DATA_DIR) + "/" + relative;
}

struct SignedDistanceKernel {
  TriangleMeshSearchView search;
  View<const Vec3> points;
  View<Real> distance;
  UNISPH_HOST_DEVICE void operator()(Index i) const { distance[i] = search.signed_distance(points[i]); }
};

struct Teapot {
  LoadedMesh loaded = load_triangle_mesh(data_file("geometry/teapot.stl"));
  TriangleMeshSearch search{loaded.mesh};

  std::vector<Vec3> points_near_surface(Index count) const {
    const TriangleMesh& mesh = loaded.mesh;
    const double band = 0.03 * norm(loaded.report.box_max - loaded.report.box_min);
    std::mt19937_64 random(2026);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::normal_distribution<double> gauss;
    std::vector<Vec3> points(count);
    for (Vec3& p : points) {
      const auto& t = mesh.triangles[random() % mesh.triangles.size()];
      double a = unit(random), b = unit(random);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      const Vec<double, 3> on = mesh.vertices[t[0]] + a * (mesh.vertices[t[1]] - mesh.vertices[t[0]]) +
                                b * (mesh.vertices[t[2]] - mesh.vertices[t[0]]);
      Vec<double, 3> direction{{gauss(random), gauss(random), gauss(random)}};
      direction /= norm(direction);
      const Vec<double, 3> x = on + direction * (band * unit(random));
      p = {{Real(x[0]), Real(x[1]), Real(x[2])}};
    }
    return points;
  }
};

// 21-bit-per-axis Morton code of p in the box [lo, hi].
std::uint64_t morton_code(const Vec3& p, const Vec<double, 3>& lo, const Vec<double, 3>& hi) {
  std::uint64_t code = 0;
  std::uint64_t cell[3];
  for (int k = 0; k < 3; ++k) {
    const double t = std::clamp((double(p[k]) - lo[k]) / (hi[k] - lo[k]), 0.0, 1.0);
    cell[k] = std::min<std::uint64_t>(std::uint64_t(t * 2097152.0), 2097151);
  }
  for (int bit = 20; bit >= 0; --bit)
    for (int k = 0; k < 3; ++k) code = (code << 1) | ((cell[k] >> bit) & 1u);
  return code;
}

Teapot& teapot() {
  static Teapot instance;
  return instance;
}

template <class P>
void ClosestPointWithSign(benchmark::State& state) {
  const Index n = static_cast<Index>(state.range(0));
  Teapot& mesh = teapot();
  DiscreteVariable<Vec3> points("QueryPoints");
  const bool morton_order = state.range(1) != 0;
  std::vector<Vec3> query = mesh.points_near_surface(n);
  if (morton_order) {
    const Vec<double, 3> lo = mesh.loaded.report.box_min * 1.1 - mesh.loaded.report.box_max * 0.1;
    const Vec<double, 3> hi = mesh.loaded.report.box_max * 1.1 - mesh.loaded.report.box_min * 0.1;
    std::sort(query.begin(), query.end(),
              [&](const Vec3& a, const Vec3& b) { return morton_code(a, lo, hi) < morton_code(b, lo, hi); });
  }
  points.assign(query);
  DiscreteVariable<Real> distance("SignedDistance", n);
  const SignedDistanceKernel kernel{mesh.search.view(P{}), points.read(P{}), distance.write(P{})};
  particle_for(P{}, n, kernel);  // warm-up: copies to the device happen here, not in the timing
  fence(P{});
  for (auto _ : state) {
    particle_for(P{}, n, kernel);
    fence(P{});
  }
  state.SetItemsProcessed(state.iterations() * int64_t(n));
  state.counters["points"] = double(n);
  state.counters["triangles"] = double(mesh.search.triangles());
  state.SetLabel("policy=" + std::string(P::name) + " precision=" + (sizeof(Real) == 8 ? "double" : "float") +
                 " N=" + std::to_string(n) + " triangles=" + std::to_string(mesh.search.triangles()) +
                 (morton_order ? " order=morton" : " order=random"));
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::RegisterBenchmark("ClosestPointWithSign<seq>", ClosestPointWithSign<SequencedPolicy>)
      ->Args({1 << 18, 0})->Args({1 << 18, 1})->Unit(benchmark::kMillisecond)->UseRealTime();
  benchmark::RegisterBenchmark("ClosestPointWithSign<par>", ClosestPointWithSign<ParallelPolicy>)
      ->Args({1 << 18, 0})->Args({1 << 18, 1})->Unit(benchmark::kMillisecond)->UseRealTime();
#if UNISPH_HAS_CUDA && defined(__CUDACC__)
  if (policy_available(PolicyKind::device))
    benchmark::RegisterBenchmark("ClosestPointWithSign<device>", ClosestPointWithSign<ParallelDevicePolicy>)
        ->Args({1 << 20, 0})->Args({1 << 23, 0})->Args({1 << 23, 1})
        ->Unit(benchmark::kMillisecond)->UseRealTime();
#endif
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
