#pragma once
// Reading closed polygons from a text file:
//
//   # a square plate with a square hole          (comments from '#' to the line end)
//   loop                                         (starts a closed loop; the closing edge is implied)
//   0 0
//   4 0
//   4 4
//   0 4
//   loop
//   1 1
//   1 2
//   2 2
//   2 1
//
// One "x y" pair per line, any number of loops, in any orientation: loops inside an odd number
// of others are holes. Repeated consecutive vertices (and a last vertex equal to the first) are
// removed and counted; each loop is turned to run counter-clockwise (outer) or clockwise (hole)
// and the turns are reported. A loop with fewer than 3 distinct vertices or zero area, a line
// that is not two finite numbers, or a vertex before the first `loop` → GeometryError with one
// line "<file>: line N: <what is wrong>". A file with no loops is valid and gives an empty set.
// Self-intersecting loops are not detected.

#include <string>
#include <string_view>

#include "unisph/geometry/geometry_error.hpp"
#include "unisph/geometry/polygon_set.hpp"

namespace unisph {

struct LoadedPolygons {
  PolygonSet polygons;
  PolygonReport report;
};

LoadedPolygons parse_polygons(std::string_view text, const std::string& source);
LoadedPolygons read_polygons(const std::string& path);

}  // namespace unisph
