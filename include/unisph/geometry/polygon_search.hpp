#pragma once
// The search structure of a polygon set: a BVH over its edges and per-edge data built on the
// host and held in DiscreteVariables; view(policy) hands kernels a PolygonSearchView in the
// policy's memory space. The polygons should come from read_polygons (oriented by nesting).

#include "unisph/exec/policy.hpp"
#include "unisph/geometry/polygon_search_view.hpp"
#include "unisph/geometry/polygon_set.hpp"
#include "unisph/memory/discrete_variable.hpp"

namespace unisph {

class PolygonSearch {
 public:
  // Throws GeometryError for a set without edges.
  explicit PolygonSearch(const PolygonSet& polygons, int leaf_size = 4);

  template <ExecutionPolicy P>
  PolygonSearchView view(P policy) {
    return {nodes_.read(policy), segments_.read(policy), normals_.read(policy), edge_index_.read(policy)};
  }

  Index edges() const { return segments_.size(); }

 private:
  DiscreteVariable<BvhNode<2>> nodes_{"PolygonBvhNodes"};
  DiscreteVariable<SegmentCorners> segments_{"PolygonSegments"};
  DiscreteVariable<SegmentPseudonormals> normals_{"PolygonPseudonormals"};
  DiscreteVariable<std::uint32_t> edge_index_{"PolygonEdgeIndex"};
};

}  // namespace unisph
