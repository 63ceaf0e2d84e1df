// libFuzzer target over the polygon reader and the 2D search built from what it reads: every
// input must give a polygon set or a GeometryError. Built and run by scripts/fuzz_stl.sh
// (UNISPH_FUZZ_TARGET=polygon).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "unisph/geometry/polygon_reader.hpp"
#include "unisph/geometry/polygon_search.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace unisph;
  LoadedPolygons loaded;
  try {
    loaded = parse_polygons(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz-input.poly");
  } catch (const GeometryError&) {
    return 0;
  }
  if (loaded.polygons.empty() || loaded.polygons.edges() > 5000) return 0;
  PolygonSearch search(loaded.polygons);
  const PolygonSearchView view = search.view(seq);
  const Vec<double, 2> centre = (loaded.report.box_min + loaded.report.box_max) * 0.5;
  for (const Vec<double, 2>& q : {centre, loaded.report.box_max, loaded.report.box_max * 2.0 - centre}) {
    const Vec<Real, 2> p{{Real(q[0]), Real(q[1])}};
    const NearestEdge n = view.nearest(p);
    if (n.edge >= loaded.polygons.edges()) std::abort();
    (void)view.sign(p, n);
  }
  return 0;
}
