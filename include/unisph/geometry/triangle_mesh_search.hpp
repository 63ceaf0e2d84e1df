#pragma once
// The search structure of a triangle mesh: a BVH and per-triangle data built on the host and
// held in DiscreteVariables, so that view(policy) hands kernels on any policy a
// TriangleMeshSearchView in the policy's memory space (copied to the device on first use).
//
//   TriangleMeshSearch search(load_triangle_mesh("part.stl").mesh);
//   particle_for(par_device, n, SignedDistanceKernel{search.view(par_device), ...});
//
// The mesh should come from load_triangle_mesh (welded, consistently oriented): the sign is
// exact only for closed, outward-oriented meshes; elsewhere use the winding number.

#include "unisph/exec/policy.hpp"
#include "unisph/geometry/triangle_mesh.hpp"
#include "unisph/geometry/triangle_mesh_search_view.hpp"
#include "unisph/memory/discrete_variable.hpp"

namespace unisph {

class TriangleMeshSearch {
 public:
  // Throws GeometryError for a mesh without triangles.
  explicit TriangleMeshSearch(const TriangleMesh& mesh, int leaf_size = 4, Real far_field_ratio = Real(2.5));

  template <ExecutionPolicy P>
  TriangleMeshSearchView view(P policy) {
    return {nodes_.read(policy), corners_.read(policy), normals_.read(policy), triangle_index_.read(policy),
            clusters_.read(policy), far_field_ratio_};
  }

  Index triangles() const { return corners_.size(); }
  Index nodes() const { return nodes_.size(); }

 private:
  DiscreteVariable<BvhNode<3>> nodes_{"MeshBvhNodes"};
  DiscreteVariable<TriangleCorners> corners_{"MeshTriangleCorners"};
  DiscreteVariable<TrianglePseudonormals> normals_{"MeshPseudonormals"};
  DiscreteVariable<std::uint32_t> triangle_index_{"MeshTriangleIndex"};
  DiscreteVariable<WindingCluster> clusters_{"MeshWindingClusters"};
  Real far_field_ratio_;
};

}  // namespace unisph
