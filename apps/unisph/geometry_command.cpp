// `unisph geometry FILE`: what was read from an STL file (or a .poly polygon file), what
// repairing it did, and the enclosed volume (area); a broken file gives its one-line error and
// a non-zero exit code (main.cpp).
#include <cstdio>
#include <memory>
#include <string>

#include "commands.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/geometry/mesh_repair.hpp"
#include "unisph/geometry/polygon_reader.hpp"
#include "unisph/geometry/triangle_mesh_search.hpp"

namespace unisph::app {

namespace {

struct GeometryOptions {
  std::string file;
  int resolution = 128;
  ExecutionOptions execution;
};

// 1 where the winding number of the cell centre exceeds 1/2, for a volume by counting cells.
struct CellInsideByWinding {
  TriangleMeshSearchView search;
  Vec<Real, 3> lo, cell;
  Index n;
  UNISPH_HOST_DEVICE double operator()(Index i) const {
    const Vec<Real, 3> p{{lo[0] + (Real(i % n) + Real(0.5)) * cell[0], lo[1] + (Real((i / n) % n) + Real(0.5)) * cell[1],
                          lo[2] + (Real(i / (n * n)) + Real(0.5)) * cell[2]}};
    return search.winding_number(p) > Real(0.5) ? 1.0 : 0.0;
  }
};

double volume_by_winding_number(const LoadedMesh& loaded, const GeometryOptions& options) {
  TriangleMeshSearch search(loaded.mesh);
  const MeshReport& r = loaded.report;
  const Index n = Index(options.resolution);
  Vec<Real, 3> lo{}, cell{};
  for (int k = 0; k < 3; ++k) {
    lo[k] = Real(r.box_min[k]);
    cell[k] = Real((r.box_max[k] - r.box_min[k]) / double(n));
  }
  const double cells = visit_policy(parse_policy(options.execution.policy), [&](auto policy) {
    return particle_reduce(policy, n * n * n, Sum<double>{}, CellInsideByWinding{search.view(policy), lo, cell, n});
  });
  return cells * double(cell[0]) * double(cell[1]) * double(cell[2]);
}

void print_report(const LoadedMesh& loaded, const GeometryOptions& options) {
  const MeshReport& r = loaded.report;
  std::printf("%s: %s, %zu solid%s, %zu facets read\n", options.file.c_str(), r.format.c_str(), r.solids,
              r.solids == 1 ? "" : "s", r.facets_read);
  std::printf("  removed facets       %zu degenerate, %zu duplicate\n", r.degenerate_facets_removed,
              r.duplicate_facets_removed);
  std::printf("  triangles            %zu\n", loaded.mesh.triangles.size());
  std::printf("  welded vertices      %zu (from %zu corners)\n", r.welded_vertices, r.corners_read);
  if (loaded.mesh.empty()) {
    std::printf("  the mesh has no triangles: no box, topology or volume\n");
    return;
  }
  std::printf("  bounding box         [%.9g, %.9g, %.9g] .. [%.9g, %.9g, %.9g]\n", r.box_min[0], r.box_min[1],
              r.box_min[2], r.box_max[0], r.box_max[1], r.box_max[2]);
  std::printf("  components           %zu (%zu closed)\n", r.components, r.closed_components);
  std::printf("  edges                %zu boundary, %zu non-manifold\n", r.boundary_edges, r.non_manifold_edges);
  std::printf("  closed               %s\n", r.closed() ? "yes" : "no");
  std::printf("  oriented             %s as read; %s after repair (%zu triangles turned for consistency)\n",
              r.consistently_oriented_as_read ? "consistently" : "inconsistently",
              r.consistently_oriented ? "consistently" : "no consistent orientation exists",
              r.triangles_flipped_for_consistency);
  std::printf("  turned outward       ");
  if (r.components_turned_outward.empty()) std::printf("none");
  for (std::size_t i = 0; i < r.components_turned_outward.size(); ++i)
    std::printf("%scomponent %zu", i ? ", " : "", r.components_turned_outward[i]);
  std::printf("\n");
  if (r.closed()) {
    std::printf("  volume               %.9g (divergence theorem)\n", r.divergence_volume);
  } else {
    const double volume = volume_by_winding_number(loaded, options);
    std::printf("  volume               %.6g (winding number > 1/2 on a %d^3 grid over the box, policy %s; the "
                "mesh is not closed)\n",
                volume, options.resolution, options.execution.policy.c_str());
  }
}

void print_polygon_report(const LoadedPolygons& loaded, const GeometryOptions& options) {
  const PolygonReport& r = loaded.report;
  std::printf("%s: polygon file, %zu loops, %zu edges\n", options.file.c_str(), r.loops, loaded.polygons.edges());
  std::printf("  removed vertices     %zu repeated\n", r.repeated_vertices_removed);
  if (loaded.polygons.empty()) {
    std::printf("  the file has no loops: no box or area\n");
    return;
  }
  std::printf("  bounding box         [%.9g, %.9g] .. [%.9g, %.9g]\n", r.box_min[0], r.box_min[1], r.box_max[0],
              r.box_max[1]);
  std::size_t holes = 0;
  for (int depth : r.depth) holes += depth % 2;
  std::printf("  loops                %zu outer, %zu holes (by nesting)\n", r.loops - holes, holes);
  std::printf("  turned               ");
  if (r.loops_turned.empty()) std::printf("none");
  for (std::size_t i = 0; i < r.loops_turned.size(); ++i) std::printf("%sloop %zu", i ? ", " : "", r.loops_turned[i]);
  std::printf("\n  area                 %.9g\n", r.area);
}

bool is_polygon_file(const std::string& file) {
  return file.size() >= 5 && file.compare(file.size() - 5, 5, ".poly") == 0;
}

}  // namespace

void add_geometry_command(CLI::App& app) {
  auto options = std::make_shared<GeometryOptions>();
  CLI::App* command = app.add_subcommand(
      "geometry", "read an STL file (or a .poly polygon file) and print what was read and repaired, whether it is "
                  "closed, and its volume (area)");
  command->add_option("file", options->file, "the STL file (binary or ASCII), or closed polygons in a .poly text file")
      ->required();
  command->add_option("--resolution", options->resolution,
                      "grid cells per axis for the volume of a mesh that is not closed (by the winding number)")
      ->check(CLI::Range(4, 2048))
      ->capture_default_str();
  add_execution_options(*command, options->execution);
  command->callback([options] {
    require_policy(parse_policy(options->execution.policy));  // before anything is printed
    if (is_polygon_file(options->file))
      print_polygon_report(read_polygons(options->file), *options);
    else
      print_report(load_triangle_mesh(options->file), *options);
  });
}

}  // namespace unisph::app
