// libFuzzer target over the STL reader and everything a read mesh goes through: parsing,
// repair (welding, removal, orientation) and, for meshes with triangles, the search structure
// and a few queries. Every input must either give a mesh or a GeometryError; any other
// exception, crash, hang or sanitizer report is a bug. Built and run by scripts/fuzz_stl.sh.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "unisph/geometry/mesh_repair.hpp"
#include "unisph/geometry/stl_reader.hpp"
#include "unisph/geometry/triangle_mesh_search.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace unisph;
  StlFacets facets;
  try {
    facets = parse_stl(std::span<const unsigned char>(data, size), "fuzz-input.stl");
  } catch (const GeometryError&) {
    return 0;  // a one-line error is the contract for a broken file
  }
  const LoadedMesh loaded = repair_triangle_mesh(facets, "fuzz-input.stl");
  if (loaded.mesh.empty() || loaded.mesh.triangles.size() > 20000) return 0;
  TriangleMeshSearch search(loaded.mesh);
  const TriangleMeshSearchView view = search.view(seq);
  const Vec<double, 3> centre = (loaded.report.box_min + loaded.report.box_max) * 0.5;
  const Vec<double, 3> corner = loaded.report.box_max;
  for (const Vec<double, 3>& q : {centre, corner, corner * 2.0 - centre}) {
    const Vec<Real, 3> p{{Real(q[0]), Real(q[1]), Real(q[2])}};
    const NearestTriangle n = view.nearest(p);
    if (n.triangle >= loaded.mesh.triangles.size()) std::abort();  // every non-empty mesh has a nearest triangle
    (void)view.sign(p, n);
    (void)view.winding_number(p);
  }
  return 0;
}
