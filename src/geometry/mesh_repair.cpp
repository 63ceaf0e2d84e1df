// Welding, facet removal and orientation of triangle meshes (host only).
#include "unisph/geometry/mesh_repair.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

#include "unisph/geometry/winding_number.hpp"

namespace unisph {

namespace {

using Vec3 = Vec<double, 3>;
using Triangle = std::array<std::uint32_t, 3>;

struct CoordinateHash {
  std::size_t operator()(const Vec3& v) const {
    std::size_t h = 1469598103934665603ull;
    for (int k = 0; k < 3; ++k) {
      std::uint64_t bits;
      std::memcpy(&bits, &v[k], sizeof bits);
      h = (h ^ bits) * 1099511628211ull;
      h ^= h >> 29;
    }
    return h;
  }
};

struct TripleHash {
  std::size_t operator()(const Triangle& t) const {
    return (std::size_t(t[0]) * 73856093u) ^ (std::size_t(t[1]) * 19349663u) ^ (std::size_t(t[2]) * 83492791u);
  }
};

// Union-find over triangles, for connected components.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), std::size_t(0)); }
  std::size_t find(std::size_t i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::size_t> parent_;
};

// One directed use of an undirected edge by a triangle.
struct EdgeUse {
  std::uint64_t key;     // (min vertex, max vertex)
  std::uint32_t triangle;
  bool forward;          // the triangle runs min -> max
};

std::vector<EdgeUse> edge_uses(const std::vector<Triangle>& triangles) {
  std::vector<EdgeUse> uses;
  uses.reserve(3 * triangles.size());
  for (std::uint32_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = triangles[t][k], b = triangles[t][(k + 1) % 3];
      uses.push_back({(std::uint64_t(std::min(a, b)) << 32) | std::max(a, b), t, a < b});
    }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return x.key != y.key ? x.key < y.key : x.triangle < y.triangle;
  });
  return uses;
}

double signed_volume(const std::vector<Vec3>& v, const Triangle& t) {
  return dot(v[t[0]], cross(v[t[1]], v[t[2]])) / 6.0;
}

void flip(Triangle& t) { std::swap(t[1], t[2]); }

}  // namespace

double divergence_volume(const TriangleMesh& mesh) {
  double volume = 0.0;
  for (const Triangle& t : mesh.triangles) volume += signed_volume(mesh.vertices, t);
  return volume;
}

void require_triangles(const TriangleMesh& mesh, const std::string& purpose) {
  if (mesh.triangles.empty())
    throw GeometryError(mesh.source + ": the mesh has no triangles; " + purpose + " needs at least one");
}

LoadedMesh repair_triangle_mesh(const StlFacets& facets, const std::string& source) {
  LoadedMesh result;
  TriangleMesh& mesh = result.mesh;
  MeshReport& report = result.report;
  mesh.source = source;
  report.format = facets.binary ? "binary STL" : "ASCII STL";
  report.solids = facets.solids;
  report.facets_read = facets.facets.size();
  report.corners_read = 3 * facets.facets.size();

  // Weld corners with identical coordinates; drop degenerate and duplicate facets.
  std::unordered_map<Vec3, std::uint32_t, CoordinateHash> vertex_of;
  std::vector<Vec3> welded;
  std::unordered_set<Triangle, TripleHash> seen;
  for (const RawTriangle& facet : facets.facets) {
    Triangle t;
    for (int c = 0; c < 3; ++c) {
      Vec3 x = facet.corner[c];
      for (int k = 0; k < 3; ++k)
        if (x[k] == 0.0) x[k] = 0.0;  // -0 and +0 weld
      const auto [it, inserted] = vertex_of.try_emplace(x, std::uint32_t(welded.size()));
      if (inserted) welded.push_back(x);
      t[c] = it->second;
    }
    const bool repeated_corner = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
    if (repeated_corner || squared_norm(cross(welded[t[1]] - welded[t[0]], welded[t[2]] - welded[t[0]])) == 0.0) {
      ++report.degenerate_facets_removed;
      continue;
    }
    Triangle sorted = t;
    std::sort(sorted.begin(), sorted.end());
    if (!seen.insert(sorted).second) {
      ++report.duplicate_facets_removed;
      continue;
    }
    mesh.triangles.push_back(t);
  }

  // Keep only the vertices the kept triangles use, in order of first use.
  std::vector<std::uint32_t> renumber(welded.size(), UINT32_MAX);
  for (Triangle& t : mesh.triangles)
    for (std::uint32_t& v : t) {
      if (renumber[v] == UINT32_MAX) {
        renumber[v] = std::uint32_t(mesh.vertices.size());
        mesh.vertices.push_back(welded[v]);
      }
      v = renumber[v];
    }
  report.welded_vertices = mesh.vertices.size();

  const std::size_t n = mesh.triangles.size();
  if (n == 0) return result;

  // Edges: count boundary and non-manifold ones, check the orientation as read, and join components.
  const std::vector<EdgeUse> uses = edge_uses(mesh.triangles);
  DisjointSets sets(n);
  std::vector<bool> open_triangle(n, false);
  struct ManifoldEdge {
    std::uint32_t t0, t1;
    bool same_direction;  // both triangles run the edge the same way: one of them must turn
  };
  std::vector<ManifoldEdge> manifold;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    const std::size_t count = j - i;
    for (std::size_t k = i + 1; k < j; ++k) sets.unite(uses[i].triangle, uses[k].triangle);
    if (count == 1) {
      ++report.boundary_edges;
      open_triangle[uses[i].triangle] = true;
    } else if (count == 2) {
      const bool same = uses[i].forward == uses[i + 1].forward;
      if (same) report.consistently_oriented_as_read = false;
      manifold.push_back({uses[i].triangle, uses[i + 1].triangle, same});
    } else {
      ++report.non_manifold_edges;
      for (std::size_t k = i; k < j; ++k) open_triangle[uses[k].triangle] = true;
    }
    i = j;
  }

  // Component ids in order of their first triangle.
  std::vector<std::size_t> component(n);
  std::unordered_map<std::size_t, std::size_t> id_of_root;
  for (std::size_t t = 0; t < n; ++t) {
    const auto [it, inserted] = id_of_root.try_emplace(sets.find(t), id_of_root.size());
    component[t] = it->second;
  }
  const std::size_t components = id_of_root.size();
  report.components = components;
  std::vector<bool> closed(components, true);
  for (std::size_t t = 0; t < n; ++t)
    if (open_triangle[t]) closed[component[t]] = false;

  // Consistent orientation: propagate "turn or keep" across manifold edges (breadth first).
  std::vector<std::vector<std::pair<std::uint32_t, bool>>> neighbours(n);
  for (const ManifoldEdge& e : manifold) {
    neighbours[e.t0].push_back({e.t1, e.same_direction});
    neighbours[e.t1].push_back({e.t0, e.same_direction});
  }
  std::vector<int> turn(n, -1);  // -1 unvisited, 0 keep, 1 turn
  std::vector<std::size_t> turned_in_component(components, 0), size_of_component(components, 0);
  std::vector<bool> orientable(components, true);
  std::vector<std::uint32_t> queue;
  for (std::uint32_t seed = 0; seed < n; ++seed) {
    if (turn[seed] != -1) continue;
    turn[seed] = 0;
    queue.assign(1, seed);
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const std::uint32_t t = queue[head];
      for (const auto& [other, same] : neighbours[t]) {
        const int wanted = turn[t] ^ int(same);
        if (turn[other] == -1) {
          turn[other] = wanted;
          queue.push_back(other);
        } else if (turn[other] != wanted) {
          orientable[component[t]] = false;  // a Möbius-like strip: no consistent orientation exists
        }
      }
    }
  }
  for (std::size_t t = 0; t < n; ++t) {
    ++size_of_component[component[t]];
    turned_in_component[component[t]] += std::size_t(turn[t]);
  }
  // Turn the minority, so that a consistent component keeps the orientation it was written with.
  // On a tie (half the triangles each way) the written orientation means nothing: a closed
  // component takes the half that leaves it with positive volume.
  std::vector<double> volume_turning_marked(components, 0.0);
  for (std::size_t t = 0; t < n; ++t)
    volume_turning_marked[component[t]] += (turn[t] == 1 ? -1.0 : 1.0) * signed_volume(mesh.vertices, mesh.triangles[t]);
  std::vector<bool> turn_the_marked(components, true);
  for (std::size_t c = 0; c < components; ++c) {
    if (2 * turned_in_component[c] > size_of_component[c])
      turn_the_marked[c] = false;
    else if (2 * turned_in_component[c] == size_of_component[c] && closed[c])
      turn_the_marked[c] = volume_turning_marked[c] >= 0.0;
  }
  for (std::size_t t = 0; t < n; ++t) {
    const std::size_t c = component[t];
    if (!orientable[c]) continue;
    if ((turn[t] == 1) == turn_the_marked[c]) {
      flip(mesh.triangles[t]);
      ++report.triangles_flipped_for_consistency;
    }
  }
  for (std::size_t c = 0; c < components; ++c)
    if (!orientable[c]) {
      report.consistently_oriented = false;
      closed[c] = false;  // without an orientation, there is no inside to point away from
    }

  // Outward orientation of closed components: the sign of the enclosed volume, corrected for nesting.
  std::vector<double> volume(components, 0.0);
  for (std::size_t t = 0; t < n; ++t) volume[component[t]] += signed_volume(mesh.vertices, mesh.triangles[t]);
  std::vector<std::size_t> closed_ids;
  for (std::size_t c = 0; c < components; ++c)
    if (closed[c]) closed_ids.push_back(c);
  report.closed_components = closed_ids.size();

  // Nesting depth: how many other closed components contain a point of this one (by the winding
  // number of each, oriented to positive volume). Quadratic in the number of closed components,
  // so only done for up to 256 of them; beyond, every closed component is taken as outermost.
  std::vector<int> depth(components, 0);
  if (closed_ids.size() > 1 && closed_ids.size() <= 256) {
    std::vector<Vec3> probe(components);
    std::vector<bool> has_probe(components, false);
    for (std::size_t t = 0; t < n; ++t) {
      const std::size_t c = component[t];
      if (closed[c] && !has_probe[c]) {
        const Triangle& tri = mesh.triangles[t];
        probe[c] = (mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) / 3.0;
        has_probe[c] = true;
      }
    }
    for (std::size_t a : closed_ids) {
      std::vector<double> angle(components, 0.0);
      for (std::size_t t = 0; t < n; ++t) {
        const std::size_t b = component[t];
        if (b == a || !closed[b]) continue;
        const Triangle& tri = mesh.triangles[t];
        angle[b] += solid_angle(probe[a], mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]);
      }
      for (std::size_t b : closed_ids) {
        if (b == a) continue;
        const double winding = angle[b] / (4.0 * pi<double>()) * (volume[b] < 0 ? -1.0 : 1.0);
        if (winding > 0.5) ++depth[a];
      }
    }
  }
  std::vector<bool> turn_component(components, false);
  for (std::size_t c : closed_ids) {
    const bool should_be_positive = depth[c] % 2 == 0;
    if ((volume[c] > 0) != should_be_positive && volume[c] != 0.0) {
      turn_component[c] = true;
      report.components_turned_outward.push_back(c);
    }
  }
  for (std::size_t t = 0; t < n; ++t)
    if (turn_component[component[t]]) flip(mesh.triangles[t]);

  report.box_min = report.box_max = mesh.vertices[0];
  for (const Vec3& v : mesh.vertices) {
    report.box_min = min(report.box_min, v);
    report.box_max = max(report.box_max, v);
  }
  report.divergence_volume = divergence_volume(mesh);
  return result;
}

LoadedMesh load_triangle_mesh(const std::string& path) { return repair_triangle_mesh(read_stl(path), path); }

}  // namespace unisph
