#pragma once
// The level set of a geometry file (a triangle mesh in 3D, polygons in 2D) at one resolution,
// and the cache that builds it once per (file, resolution) for every shape and body that uses it.
//
//   shape::MeshLevelSetCache<3> cache;
//   auto hull = shape::triangle_mesh(cache, "hull.stl", dx);     // builds the level set
//   auto copy = shape::triangle_mesh(cache, "hull.stl", dx);     // the same level set, no rebuild
//
// 3D: load_triangle_mesh (read + weld + remove + orient, docs/geometry.md), signed by the winding
// number (right also for meshes that leak or hold inner walls); 2D: read_polygons. By default phi
// is the exact signed distance at the data points (no small-feature cleaning: it would also blunt
// sharp tips, e.g. moving phi by 1.7 dx next to a 28-degree corner of plate_with_holes.poly);
// clean_small_features = true removes features thinner than about one data spacing
// (docs/levelset.md). No kernel integrals are built.

#include <filesystem>
#include <cmath>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>

#include "unisph/core/error.hpp"
#include "unisph/exec/policy.hpp"
#include "unisph/geometry/mesh_repair.hpp"
#include "unisph/geometry/polygon_reader.hpp"
#include "unisph/levelset/multi_resolution_level_set.hpp"
#include "unisph/levelset/shape_search.hpp"

namespace unisph::shape {

template <int D>
class MeshLevelSet {
  static_assert(D == 2 || D == 3, "a mesh level set is built from polygons (2D) or a triangle mesh (3D).");

 public:
  template <ExecutionPolicy P>
  MeshLevelSet(P policy, const std::string& path, Real resolution, bool clean_small_features = false)
      : path_(path), resolution_(resolution) {
    if (!(resolution > Real(0)) || !std::isfinite(resolution)) {
      std::ostringstream message;
      message << path << ": the level-set resolution must be positive, got " << resolution;
      throw Error(message.str());
    }
    if constexpr (D == 3) {
      const LoadedMesh loaded = load_triangle_mesh(path);
      require_triangles(loaded.mesh, "a triangle-mesh shape");
      for (int k = 0; k < 3; ++k) {
        lower_[k] = Real(loaded.report.box_min[k]);
        upper_[k] = Real(loaded.report.box_max[k]);
      }
      TriangleMeshSearch search(loaded.mesh);
      level_set_ = std::make_unique<MultiResolutionLevelSet<3>>(
          policy, WindingNumberSign<TriangleMeshSearchView>{search.view(policy)}, lower_, upper_, resolution, 0, false,
          clean_small_features);
    } else {
      const LoadedPolygons loaded = read_polygons(path);
      PolygonSearch search(loaded.polygons);  // refuses a file without loops
      lower_ = upper_ = Vec<Real, 2>{{Real(loaded.polygons.vertices[0][0]), Real(loaded.polygons.vertices[0][1])}};
      for (const auto& v : loaded.polygons.vertices)
        for (int k = 0; k < 2; ++k) {
          lower_[k] = Real(v[k]) < lower_[k] ? Real(v[k]) : lower_[k];
          upper_[k] = Real(v[k]) > upper_[k] ? Real(v[k]) : upper_[k];
        }
      level_set_ = std::make_unique<MultiResolutionLevelSet<2>>(policy, search.view(policy), lower_, upper_, resolution,
                                                                0, false, clean_small_features);
    }
  }

  const std::string& path() const { return path_; }
  Real resolution() const { return resolution_; }
  // The bounding box of the geometry (the level set's grid extends two coarse cells beyond it).
  const Vec<Real, D>& lower() const { return lower_; }
  const Vec<Real, D>& upper() const { return upper_; }
  MultiResolutionLevelSet<D>& level_set() { return *level_set_; }

 private:
  std::string path_;
  Real resolution_;
  Vec<Real, D> lower_{}, upper_{};
  std::unique_ptr<MultiResolutionLevelSet<D>> level_set_;
};

template <int D>
class MeshLevelSetCache {
 public:
  // The level set of `path` at `resolution`, built on `policy` on first request. Paths naming
  // the same existing file are one entry.
  template <ExecutionPolicy P>
  std::shared_ptr<MeshLevelSet<D>> get(P policy, const std::string& path, Real resolution,
                                       bool clean_small_features = false) {
    std::error_code error;
    std::string file = std::filesystem::weakly_canonical(path, error).string();
    if (error) file = path;
    const Key key{file, resolution, clean_small_features};
    const auto found = entries_.find(key);
    if (found != entries_.end()) return found->second;
    // May throw: then nothing is cached.
    auto built = std::make_shared<MeshLevelSet<D>>(policy, path, resolution, clean_small_features);
    entries_.emplace(key, built);
    return built;
  }
  std::size_t size() const { return entries_.size(); }

 private:
  using Key = std::tuple<std::string, Real, bool>;
  std::map<Key, std::shared_ptr<MeshLevelSet<D>>> entries_;
};

}  // namespace unisph::shape
