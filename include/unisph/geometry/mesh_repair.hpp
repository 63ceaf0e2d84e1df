#pragma once
// From raw STL facets to a triangle mesh that distance and sign queries can trust:
//   - corners with identical coordinates are welded into one vertex (exact match: STL stores
//     shared corners bit for bit; -0 and +0 are one value);
//   - degenerate facets (two corners welded together, or zero area) are removed and counted;
//   - duplicate facets (the same three vertices as an earlier one, in either orientation) too;
//   - each connected component is oriented consistently (triangles turned to agree with the
//     majority across shared edges), and each closed component outward: positive enclosed
//     volume, or negative for a component nested inside an odd number of others (a cavity);
//     the components turned are listed in the report.
// Stored facet normals are never used. An empty mesh is valid; require_triangles refuses it
// where triangles are needed.

#include <string>

#include "unisph/geometry/stl_reader.hpp"
#include "unisph/geometry/triangle_mesh.hpp"

namespace unisph {

struct LoadedMesh {
  TriangleMesh mesh;
  MeshReport report;
};

// Welds, removes and orients as described above.
LoadedMesh repair_triangle_mesh(const StlFacets& facets, const std::string& source);

// read_stl + repair_triangle_mesh.
LoadedMesh load_triangle_mesh(const std::string& path);

// Throws GeometryError "<source>: the mesh has no triangles; <purpose> needs at least one".
void require_triangles(const TriangleMesh& mesh, const std::string& purpose);

// Sum of the signed volumes of the tetrahedra (origin, triangle): the enclosed volume of a
// closed, outward-oriented mesh.
double divergence_volume(const TriangleMesh& mesh);

}  // namespace unisph
