// Closest point with sign on the teapot (teapot.stl, 9438 triangles): queries per second on
// every policy this build has. The query points lie within 3 % of the teapot's size (its box
// diagonal) from the surface: a point on a random triangle moved by up to that distance in a
// random direction. Each query finds the nearest triangle through the BVH and signs the
// distance by the angle-weighted pseudonormal: what a level-set build does per grid point.
//
//   ClosestPointWithSign<policy>/N    items_per_second = queries/s; label: policy, precision, N, triangles
//
// The data folder is the source tree's tests/data, or $UNISPH_TEST_DATA_DIR where set.
#include <benchmark/benchmark.h>

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

Teapot& teapot() {
  static Teapot instance;
  return instance;
}

template <class P>
void ClosestPointWithSign(benchmark::State& state) {
  const Index n = static_cast<Index>(state.range(0));
  Teapot& mesh = teapot();
  DiscreteVariable<Vec3> points("QueryPoints");
  points.assign(mesh.points_near_surface(n));
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
                 " N=" + std::to_string(n) + " triangles=" + std::to_string(mesh.search.triangles()));
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::RegisterBenchmark("ClosestPointWithSign<seq>", ClosestPointWithSign<SequencedPolicy>)
      ->Arg(1 << 18)->Unit(benchmark::kMillisecond)->UseRealTime();
  benchmark::RegisterBenchmark("ClosestPointWithSign<par>", ClosestPointWithSign<ParallelPolicy>)
      ->Arg(1 << 18)->Unit(benchmark::kMillisecond)->UseRealTime();
#if UNISPH_HAS_CUDA && defined(__CUDACC__)
  if (policy_available(PolicyKind::device))
    benchmark::RegisterBenchmark("ClosestPointWithSign<device>", ClosestPointWithSign<ParallelDevicePolicy>)
        ->Arg(1 << 20)->Arg(1 << 23)->Unit(benchmark::kMillisecond)->UseRealTime();
#endif
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
