#pragma once
// A level set of a closed shape (triangle mesh in 3D, polygons in 2D) on layers of doubling
// resolution down to the requested data spacing, built on any policy:
//
//   TriangleMeshSearch search(load_triangle_mesh("part.stl").mesh);
//   MultiResolutionLevelSet<3> level_set(par_device, search.view(par_device), lo, hi, dx);
//   particle_for(par_device, n, MyKernel{level_set.view(par_device), ...});   // probes in kernels
//
// Stages, each timed (stage_seconds):
//   tagging    coarsest layer: every cell core (surface within one cell size of the centre) or
//              not; the cells without surface take the side of their connected region (the one
//              at the grid border outside, the others by a vote of their cells' signs), so the
//              inside is closed even where the surface leaks and 2D holes and 3D cavities are
//              right (outside_flood_fill.hpp); finer layers: only the children of
//              coarse cells with packages are evaluated, the others inherit their parent's side
//              (on the host with a triangle mesh the coarse layer's distance stage decided them);
//              then inner cells around the core
//   packages   allocation sorted by Morton key (same layout on every policy and run), the
//              neighbourhood tables
//   distance   phi at every data point: exact distance to the surface (BVH closest point), the
//              sign from the shape (pseudonormal or winding number) in core packages, from the
//              cell's side in inner ones
//   normals    regularised central difference of phi
//   cleaning   finest layer only (skipped when clean_small_features is false): features thinner
//              than about one data spacing removed by re-distancing (small_feature_cleaning.hpp),
//              then the normals again where something was removed
//   kernel integrals   of the Wendland kernel (h = 1.3 finest dx) and its gradient over the
//                      outside (kernel_integrals.hpp; skipped when with_kernel_integrals is
//                      false, and then not to be probed)
//
// The grid: cells of the coarsest layer are 4 * dx * 2^(levels - 1) wide; the box [lo, hi] is
// padded by two coarse cells on every side, so the border of the grid is far field.

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "unisph/core/error.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/levelset/band_tagging.hpp"
#include "unisph/levelset/level_set_layer.hpp"
#include "unisph/levelset/multi_resolution_level_set_view.hpp"
#include "unisph/levelset/outside_flood_fill.hpp"
#include "unisph/levelset/shape_search.hpp"
#include "unisph/levelset/small_feature_cleaning.hpp"

namespace unisph {

struct LevelSetStageTimes {
  double tagging = 0, packages = 0, distance = 0, normals = 0, cleaning = 0, kernel_integrals = 0;
};

template <int D>
class MultiResolutionLevelSet {
 public:
  static constexpr int dimension = D;

  // levels = 0 picks as many as keep the coarsest layer at 32 or more cells along the box's
  // longest side. A coarser layer is no longer sparse and only costs: at 16 cells teapot.stl put
  // packages on 40 % of the cells, and their data points, far from a surface of many small
  // triangles, each need the exact distance to a hundred of them (4-5 us a point): that layer
  // took 10 % of the build at N = 1024 for 0.4 % of the data points (docs/levelset.md).
  // shape: ShapeSearchView<D> in the policy's memory space, or any trivially copyable object
  // with the same nearest(p).squared_distance and sign(p, nearest) (analytic shapes in tests).
  // clean_small_features: false keeps phi the exact signed distance of the shape.
  template <ExecutionPolicy P, class Shape>
  MultiResolutionLevelSet(P policy, const Shape& shape, const Vec<Real, D>& lo, const Vec<Real, D>& hi,
                          Real data_spacing, int levels = 0, bool with_kernel_integrals = true,
                          bool clean_small_features = true)
      : with_kernel_integrals_(with_kernel_integrals),
        clean_small_features_(clean_small_features),
        smoothing_length_(WendlandC2Kernel<Real, D>::smoothing_length_ratio * data_spacing) {
    if (!(data_spacing > Real(0))) throw Error("level set: the data spacing must be positive");
    Real longest = Real(0);
    for (int k = 0; k < D; ++k) longest = hi[k] - lo[k] > longest ? hi[k] - lo[k] : longest;
    if (levels <= 0) {
      levels = 1;
      while (levels < max_level_set_layers && longest / (Real(package_size) * data_spacing * Real(1 << levels)) >= Real(32))
        ++levels;
    }
    if (levels > max_level_set_layers)
      throw Error("level set: at most " + std::to_string(max_level_set_layers) + " levels");
    const Real coarse_cell = Real(package_size) * data_spacing * Real(1 << (levels - 1));
    PackageGrid<D> grid;
    for (int k = 0; k < D; ++k) {
      grid.origin[k] = lo[k] - Real(2) * coarse_cell;
      grid.cells[k] = int(std::ceil((hi[k] - lo[k]) / coarse_cell)) + 4;
    }
    grid.data_spacing = data_spacing * Real(1 << (levels - 1));
    for (int level = 0; level < levels; ++level) {
      layers_.push_back(std::make_unique<LevelSetLayer<D>>(grid));
      grid.data_spacing = grid.data_spacing / Real(2);
      for (int k = 0; k < D; ++k) grid.cells[k] *= 2;
    }
    for (int level = 0; level < levels; ++level) build_layer(policy, shape, level);
    // The per-cell tags only serve the build of the next layer.
    for (auto& layer : layers_) {
      layer->tags.resize(0);
      layer->cell_side.resize(0);
    }
  }

  int levels() const { return int(layers_.size()); }
  LevelSetLayer<D>& layer(int level) { return *layers_[level]; }
  LevelSetLayer<D>& finest() { return *layers_.back(); }
  const LevelSetStageTimes& stage_seconds() const { return times_; }
  // Data points of the finest layer that small-feature cleaning removed (0 when it was off).
  Index removed_data_points() const { return removed_; }

  template <ExecutionPolicy P>
  MultiResolutionLevelSetView<D> view(P policy) {
    MultiResolutionLevelSetView<D> v{};
    v.levels = levels();
    for (int level = 0; level < levels(); ++level) v.layer[level] = layers_[level]->view(policy);
    return v;
  }

 private:
  template <ExecutionPolicy P, class Shape>
  void build_layer(P policy, const Shape& shape, int level) {
    LevelSetLayer<D>& layer = *layers_[level];
    const PackageGrid<D> grid = layer.grid();
    const Index cells = grid.cell_count();
    using Clock = std::chrono::steady_clock;
    auto t0 = Clock::now();
    DiscreteVariable<CellTag>& decided = layer.cell_side;
    if (level == 0) {
      View<CellTag> tags = decided.write(policy);
      particle_for(policy, cells, TagEveryCell<D, Shape>{shape, grid, tags});
      // The cells without surface: each region's side (outside_flood_fill.hpp).
      DiscreteVariable<std::uint32_t> label("CellRegion", cells), spare("CellRegionSweep", cells);
      DiscreteVariable<int> votes("CellRegionVotes", cells);
      particle_for(policy, cells, StartRegions<D>{grid, decided.read(policy), label.write(policy), votes.write(policy)});
      // Sweeps between two arrays until one changes nothing: then both hold the labels.
      for (bool into_spare = true;; into_spare = !into_spare) {
        DiscreteVariable<std::uint32_t>& from = into_spare ? label : spare;
        DiscreteVariable<std::uint32_t>& to = into_spare ? spare : label;
        if (particle_reduce(policy, cells, Sum<Index>{}, MergeRegions<D>{grid, from.read(policy), to.write(policy)}) == 0)
          break;
      }
      particle_for(policy, cells, VoteRegionSide<D>{decided.read(policy), label.read(policy), votes.read_write(policy)});
      particle_for(policy, cells, SideOfRegion<D>{label.read(policy), votes.read(policy), decided.read_write(policy)});
    } else {
      LevelSetLayer<D>& coarse = *layers_[level - 1];
      if constexpr (D == 3 && P::space == MemorySpace::host && searches_triangle_mesh<Shape>)
        particle_for(policy, coarse.grid().cell_count(),
                     TagChildrenFromCoarsePackages{grid, coarse.grid(), coarse.tags.read(policy),
                                                   coarse.mesh.cell_package.read(policy),
                                                   coarse.children_tag.read(policy), decided.write(policy)});
      else
        particle_for(policy, cells,
                     TagUnderCoarseBand<D, Shape>{shape, grid, coarse.grid(), coarse.tags.read(policy),
                                                  decided.write(policy)});
    }
    if (level == 0) {
      particle_for(policy, cells, TagInner<D>{grid, decided.read(policy), layer.tags.write(policy)});
    } else {
      LevelSetLayer<D>& coarse = *layers_[level - 1];
      particle_for(policy, cells, CopyCellTags{decided.read(policy), layer.tags.write(policy)});
      particle_for(policy, coarse.data_packages() * (Index(1) << D),
                   TagInnerUnderCoarsePackages<D>{grid, coarse.grid(), coarse.mesh.package_cell.read(policy),
                                                  decided.read(policy), layer.tags.read_write(policy)});
    }
    fence(policy);
    auto t1 = Clock::now();
    layer.allocate_packages(policy);
    auto t2 = Clock::now();
    // On the host with a triangle mesh the distance stage also decides the next layer's cells
    // under this layer's packages (SignedDistanceInPackages), and starts from the distances the
    // layer above found for this layer's cell centres.
    const PackageGrid<D> finer = level + 1 < levels() ? layers_[level + 1]->grid() : PackageGrid<D>{};
    layer.compute_signed_distance(policy, shape, level > 0 ? layers_[level - 1].get() : nullptr,
                                  level + 1 < levels() ? &finer : nullptr);
    if (level > 0) {
      layers_[level - 1]->children_tag.resize(0);
      layers_[level - 1]->children_distance2.resize(0);
    }
    auto t3 = Clock::now();
    layer.compute_normals(policy);
    auto t4 = Clock::now();
    if (clean_small_features_ && level + 1 == levels()) {
      removed_ = clean_small_features(policy, layer.mesh, layer.phi, layer.normal);
      if (removed_ > 0) layer.compute_normals(policy);
    }
    auto t5 = Clock::now();
    if (with_kernel_integrals_) layer.compute_kernel_integrals(policy, smoothing_length_);
    times_.kernel_integrals += std::chrono::duration<double>(Clock::now() - t5).count();
    times_.cleaning += std::chrono::duration<double>(t5 - t4).count();
    times_.tagging += std::chrono::duration<double>(t1 - t0).count();
    times_.packages += std::chrono::duration<double>(t2 - t1).count();
    times_.distance += std::chrono::duration<double>(t3 - t2).count();
    times_.normals += std::chrono::duration<double>(t4 - t3).count();
  }

  std::vector<std::unique_ptr<LevelSetLayer<D>>> layers_;
  LevelSetStageTimes times_;
  bool with_kernel_integrals_;
  bool clean_small_features_;
  Index removed_ = 0;
  Real smoothing_length_;  // of the kernel integrals: 1.3 times the finest data spacing
};

}  // namespace unisph
