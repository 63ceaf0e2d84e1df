#pragma once
// Closed polygons in the plane (several, with holes), on the host: vertices of all loops in one
// array, loop k being vertices [loop_start[k], loop_start[k + 1]) with an implied closing edge.
// After read_polygons, outer boundaries run counter-clockwise and holes clockwise (by nesting
// depth), so the outward normal of every edge points to the right of its direction.

#include <cstdint>
#include <string>
#include <vector>

#include "unisph/core/vector.hpp"

namespace unisph {

struct PolygonSet {
  std::string source;
  std::vector<Vec<double, 2>> vertices;
  std::vector<std::uint32_t> loop_start{0};  // loops() + 1 entries

  std::size_t loops() const { return loop_start.size() - 1; }
  std::size_t edges() const { return vertices.size(); }
  bool empty() const { return vertices.empty(); }
};

struct PolygonReport {
  std::size_t loops = 0;
  std::size_t repeated_vertices_removed = 0;  // a vertex equal to the one before it (or the first one closing the loop)
  std::vector<std::size_t> loops_turned;      // loops whose orientation did not match their nesting depth
  std::vector<int> depth;                     // per loop: 0 outer boundary, 1 hole, 2 island in a hole...
  double area = 0.0;                          // enclosed area (holes subtracted)
  Vec<double, 2> box_min{}, box_max{};
};

}  // namespace unisph
