#pragma once
// A triangle mesh on the host: welded vertices and triangles as vertex-index triples, with
// the report of what reading and repairing it did. Built by load_triangle_mesh (mesh_repair.hpp)
// from the facets of an STL file; the query structures are built from it.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "unisph/core/vector.hpp"

namespace unisph {

// One facet as it was in the file: three corners, stored normals dropped (they are never trusted).
struct RawTriangle {
  std::array<Vec<double, 3>, 3> corner;
};

struct TriangleMesh {
  std::string source;  // the file (or a description) it came from, for messages
  std::vector<Vec<double, 3>> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;

  bool empty() const { return triangles.empty(); }
};

// What load_triangle_mesh did and found. Counts refer to the mesh after repair unless named "_as_read".
struct MeshReport {
  std::string format;          // "binary STL" or "ASCII STL"
  std::size_t solids = 0;      // ASCII `solid` blocks (1 for binary files)
  std::size_t facets_read = 0;
  std::size_t degenerate_facets_removed = 0;  // two corners welded into one, or zero area
  std::size_t duplicate_facets_removed = 0;   // same three vertices as an earlier facet, in any order
  std::size_t corners_read = 0;               // 3 per facet read
  std::size_t welded_vertices = 0;            // distinct vertices used by the kept triangles

  std::size_t components = 0;          // connected through shared edges
  std::size_t closed_components = 0;   // every edge shared by exactly two triangles of the component
  std::size_t boundary_edges = 0;      // edges with one triangle
  std::size_t non_manifold_edges = 0;  // edges with three or more triangles
  bool consistently_oriented_as_read = true;  // every manifold edge traversed once each way, before repair
  std::size_t triangles_flipped_for_consistency = 0;  // turned to agree with their component's majority
  std::vector<std::size_t> components_turned_outward;  // closed components that were inside-out (ids)
  bool consistently_oriented = true;  // after repair (false only where no orientation is consistent)
  bool closed() const { return components > 0 && closed_components == components && non_manifold_edges == 0; }

  Vec<double, 3> box_min{}, box_max{};  // bounding box of the kept vertices
  double divergence_volume = 0.0;       // sum of signed tetrahedron volumes (exact for closed meshes)
};

}  // namespace unisph
