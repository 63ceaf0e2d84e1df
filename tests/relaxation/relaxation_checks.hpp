#pragma once
// What the relaxation tests measure on a particle set (host side, from the variables): the
// zero-order consistency error |Σ_j ∇W_ij V_j + G| h per particle (mean, 99th percentile,
// largest), the share of particles whose kernel sum Σ_j W_ij V_j + S lies within ±3 % of the
// full lattice's, the largest phi (how far a particle lies outside), the particle count, the ids
// and the total volume.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "unisph/geometry/mesh_repair.hpp"
#include "unisph/geometry/polygon_reader.hpp"
#include "unisph/relaxation/particle_relaxation.hpp"
#include "unisph/relaxation/relaxation_level_set.hpp"

namespace unisph::testing {

struct RelaxedSetState {
  Index particles = 0;
  double mean_error = 0, p99_error = 0, max_error = 0;
  double kernel_sum_within_3_percent = 0;  // share of particles
  double largest_phi = 0;                  // > 0: outside the body
  // The same error apart for the particles within 2h of the surface and for the others.
  double surface_mean = 0, surface_max = 0, bulk_mean = 0, bulk_max = 0;
  Index surface_particles = 0;
  double total_volume = 0;
  bool ids_are_a_permutation = false;
};

template <int D, ExecutionPolicy P>
RelaxedSetState measure_state(P policy, ParticleRelaxation<D>& relaxation) {
  relaxation.measure(policy);
  relaxation.surface_distances(policy);
  const Real h = relaxation.kernel().h;
  const std::vector<Vec<Real, D>> residual = relaxation.residuals().to_vector();
  const std::vector<Real> sum = relaxation.kernel_sums().to_vector();
  const std::vector<Real> phi = relaxation.normal_distances().to_vector();
  const std::vector<Real> volume = relaxation.volumes().to_vector();
  std::vector<std::uint64_t> ids = relaxation.body().particles().ids().to_vector();
  RelaxedSetState s;
  s.particles = residual.size();
  std::vector<double> error(residual.size());
  const double lattice = double(relaxation.kernel().lattice_sum(relaxation.spacing())) *
                         std::pow(double(relaxation.spacing()), D);
  Index within = 0;
  s.largest_phi = -1e300;
  for (std::size_t i = 0; i < residual.size(); ++i) {
    error[i] = double(norm(residual[i])) * double(h) / 2;  // |a| = 2 |g|
    s.mean_error += error[i];
    within += std::abs(double(sum[i]) - lattice) <= 0.03 * lattice;
    s.largest_phi = std::max(s.largest_phi, double(phi[i]));
    s.total_volume += double(volume[i]);
    if (double(phi[i]) > -2 * double(h) && double(phi[i]) < 2 * double(h)) {
      ++s.surface_particles;
      s.surface_mean += error[i];
      s.surface_max = std::max(s.surface_max, error[i]);
    } else {
      s.bulk_mean += error[i];
      s.bulk_max = std::max(s.bulk_max, error[i]);
    }
  }
  if (s.surface_particles > 0) s.surface_mean /= double(s.surface_particles);
  if (residual.size() > s.surface_particles) s.bulk_mean /= double(residual.size() - s.surface_particles);
  s.mean_error /= double(error.size());
  std::sort(error.begin(), error.end());
  s.max_error = error.back();
  s.p99_error = error[std::size_t(0.99 * double(error.size() - 1))];
  s.kernel_sum_within_3_percent = double(within) / double(residual.size());
  std::sort(ids.begin(), ids.end());
  s.ids_are_a_permutation = true;
  for (std::size_t k = 0; k < ids.size(); ++k) s.ids_are_a_permutation &= ids[k] == k;
  return s;
}

inline void print_state(const char* label, const RelaxedSetState& s) {
  std::printf("  %-8s n %zu  error mean %.3e p99 %.3e max %.3e  kernel sum within 3%%: %.4f  largest phi %.3e  "
              "volume %.6f\n",
              label, s.particles, s.mean_error, s.p99_error, s.max_error, s.kernel_sum_within_3_percent,
              s.largest_phi, s.total_volume);
  std::printf("  %-8s within 2h of the surface: %zu, error mean %.3e max %.3e;  bulk: error mean %.3e max %.3e\n", "",
              std::size_t(s.surface_particles), s.surface_mean, s.surface_max, s.bulk_mean, s.bulk_max);
}

// A geometry ready to relax: its level set (spacing dx) and its box.
template <int D>
struct RelaxationGeometry {
  Box<Real, D> box;
  double enclosed = 0;  // mesh volume (divergence theorem) or polygon area
  std::unique_ptr<ShapeSearch<D>> search;
  std::unique_ptr<MultiResolutionLevelSet<D>> level_set;

  // The particles inside, seeded by the winding number (see lattice_seeding.hpp).
  template <ExecutionPolicy P>
  std::unique_ptr<ParticleRelaxation<D>> relaxation(P policy, Real dx) {
    return std::make_unique<ParticleRelaxation<D>>(policy, *level_set, box, SeedRegion::inside, dx,
                                                    WindingNumberSide<ShapeSearchView<D>>{search->view(policy), true});
  }
};

template <int D, ExecutionPolicy P>
RelaxationGeometry<D> load_relaxation_geometry(P policy, const std::string& path, Real dx) {
  RelaxationGeometry<D> g;
  if constexpr (D == 3) {
    const LoadedMesh loaded = load_triangle_mesh(path);
    for (int k = 0; k < 3; ++k) g.box.lower[k] = Real(loaded.report.box_min[k]), g.box.upper[k] = Real(loaded.report.box_max[k]);
    g.enclosed = loaded.report.divergence_volume;
    g.search = std::make_unique<TriangleMeshSearch>(loaded.mesh);
    g.level_set = make_relaxation_level_set<3>(policy, *g.search, g.box, dx);
  } else {
    const LoadedPolygons loaded = read_polygons(path);
    for (int k = 0; k < 2; ++k) g.box.lower[k] = Real(loaded.report.box_min[k]), g.box.upper[k] = Real(loaded.report.box_max[k]);
    g.enclosed = loaded.report.area;
    g.search = std::make_unique<PolygonSearch>(loaded.polygons);
    g.level_set = make_relaxation_level_set<2>(policy, *g.search, g.box, dx);
  }
  return g;
}

}  // namespace unisph::testing
