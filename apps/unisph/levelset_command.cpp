// `unisph levelset GEOMETRY --dx DX [--levels L] [--sign winding|pseudonormal] [--policy ...] -o DIR`:
// builds the multi-resolution level set of an STL file (3D) or a .poly polygon file (2D),
// prints per layer its packages, data points and memory per data point and the time of every
// stage, and writes one VTK PolyData file per layer (DIR/levelset_layer_<l>.vtp: the data
// points with phi, normal, kernel weight and gradient, package type and index) for ParaView.
// A geometry that cannot make a level set (refused by the reader, or without triangles or
// loops) stops with one line on stderr before anything is written.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/geometry/geometry_error.hpp"
#include "unisph/geometry/mesh_repair.hpp"
#include "unisph/geometry/polygon_reader.hpp"
#include "unisph/io/vtk_xml_writer.hpp"
#include "unisph/levelset/multi_resolution_level_set.hpp"

namespace unisph::app {

namespace {

struct LevelSetOptions {
  std::string file;
  std::string output;
  double dx = 0;
  int levels = 0;
  std::string sign = "winding";
  bool no_cleaning = false;
  ExecutionOptions execution;
};

template <int D>
void write_layer(const std::filesystem::path& path, LevelSetLayer<D>& layer) {
  const std::vector<std::uint64_t> cells = layer.mesh.package_cell.to_vector();
  const std::vector<PackageType> types = layer.mesh.package_type.to_vector();
  const std::vector<Real> phi = layer.phi.to_vector(), weight = layer.kernel_weight.to_vector();
  const std::vector<Vec<Real, D>> normal = layer.normal.to_vector(), gradient = layer.kernel_gradient.to_vector();
  std::vector<Real> points, phi_out, normal_out, weight_out, gradient_out;
  std::vector<std::uint64_t> type_out, package_out;
  for (Index p = far_field_packages; p < layer.packages(); ++p)
    for (int l = 0; l < package_points<D>; ++l) {
      const Index i = p * package_points<D> + l;
      const Vec<Real, D> x = layer.grid().data_position(layer.grid().coordinates(cells[p]), l);
      for (int k = 0; k < 3; ++k) {
        points.push_back(k < D ? x[k] : Real(0));
        normal_out.push_back(k < D ? normal[i][k] : Real(0));
        gradient_out.push_back(k < D ? gradient[i][k] : Real(0));
      }
      phi_out.push_back(phi[i]);
      weight_out.push_back(weight[i]);
      type_out.push_back(std::uint64_t(types[p]));
      package_out.push_back(p);
    }
  io::write_vtp(path, points,
                {io::PointArray::from("phi", 1, phi_out), io::PointArray::from("normal", 3, normal_out),
                 io::PointArray::from("kernel_weight", 1, weight_out),
                 io::PointArray::from("kernel_gradient", 3, gradient_out),
                 io::PointArray::from("package_type", 1, type_out), io::PointArray::from("package", 1, package_out)});
}

template <int D, class Search>
void build_and_report(Search& search, const Vec<Real, D>& lo, const Vec<Real, D>& hi, const LevelSetOptions& options) {
  const bool winding = options.sign == "winding";
  const auto start = std::chrono::steady_clock::now();
  std::unique_ptr<MultiResolutionLevelSet<D>> level_set;
  visit_policy(parse_policy(options.execution.policy), [&](auto policy) {
    if (winding)
      level_set = std::make_unique<MultiResolutionLevelSet<D>>(
          policy, WindingNumberSign<ShapeSearchView<D>>{search.view(policy)}, lo, hi, Real(options.dx), options.levels,
          true, !options.no_cleaning);
    else
      level_set = std::make_unique<MultiResolutionLevelSet<D>>(policy, search.view(policy), lo, hi, Real(options.dx),
                                                               options.levels, true, !options.no_cleaning);
    fence(policy);
  });
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%s: %dD level set, data spacing %.6g, %d layers, policy %s, sign by %s\n", options.file.c_str(), D,
              options.dx, level_set->levels(), options.execution.policy.c_str(),
              winding ? "winding number" : "pseudonormal");
  std::printf("  layer  spacing       cells       packages (core + inner)        data points   bytes/point\n");
  for (int l = 0; l < level_set->levels(); ++l) {
    LevelSetLayer<D>& layer = level_set->layer(l);
    Index core = 0;
    for (PackageType t : layer.mesh.package_type.to_vector()) core += t == PackageType::core;
    std::printf("  %5d  %-12.6g  %-10zu  %-9zu (%zu + %zu)  %14zu  %.2f\n", l, double(layer.grid().data_spacing),
                layer.grid().cell_count(), layer.data_packages(), core, layer.data_packages() - core,
                layer.data_packages() * package_points<D>, layer.bytes_per_data_point());
  }
  const LevelSetStageTimes& t = level_set->stage_seconds();
  if (!options.no_cleaning)
    std::printf("  small-feature cleaning removed %zu data points of the finest layer\n",
                std::size_t(level_set->removed_data_points()));
  std::printf("  time   tagging %.3f s, packages %.3f s, distance %.3f s, normals %.3f s, cleaning %.3f s, kernel "
              "integrals %.3f s, total %.3f s\n",
              t.tagging, t.packages, t.distance, t.normals, t.cleaning, t.kernel_integrals, total);
  std::filesystem::create_directories(options.output);
  for (int l = 0; l < level_set->levels(); ++l)
    write_layer<D>(std::filesystem::path(options.output) / ("levelset_layer_" + std::to_string(l) + ".vtp"),
                   level_set->layer(l));
  std::printf("  wrote  %s/levelset_layer_{0..%d}.vtp\n", options.output.c_str(), level_set->levels() - 1);
}

bool is_polygon_file(const std::string& file) {
  return file.size() >= 5 && file.compare(file.size() - 5, 5, ".poly") == 0;
}

void run(const LevelSetOptions& options) {
  require_policy(parse_policy(options.execution.policy));  // before anything is read or printed
  if (is_polygon_file(options.file)) {
    const LoadedPolygons loaded = read_polygons(options.file);
    if (loaded.polygons.empty())
      throw GeometryError(options.file + ": the file has no loops; a level set needs at least one");
    PolygonSearch search(loaded.polygons);
    Vec<Real, 2> lo, hi;
    for (int k = 0; k < 2; ++k) lo[k] = Real(loaded.report.box_min[k]), hi[k] = Real(loaded.report.box_max[k]);
    build_and_report<2>(search, lo, hi, options);
  } else {
    const LoadedMesh loaded = load_triangle_mesh(options.file);
    require_triangles(loaded.mesh, "a level set");
    TriangleMeshSearch search(loaded.mesh);
    Vec<Real, 3> lo, hi;
    for (int k = 0; k < 3; ++k) lo[k] = Real(loaded.report.box_min[k]), hi[k] = Real(loaded.report.box_max[k]);
    build_and_report<3>(search, lo, hi, options);
  }
}

}  // namespace

void add_levelset_command(CLI::App& app) {
  auto options = std::make_shared<LevelSetOptions>();
  CLI::App* command = app.add_subcommand(
      "levelset", "build the multi-resolution level set of an STL file (or a .poly polygon file), print its layers "
                  "and stage times, and write one VTK file per layer");
  command->add_option("file", options->file, "the STL file (binary or ASCII), or closed polygons in a .poly text file")
      ->required();
  command->add_option("--dx", options->dx, "data spacing of the finest layer")->required()->check(CLI::PositiveNumber);
  command->add_option("--levels", options->levels, "layers of doubling spacing (0: coarsest keeps >= 32 cells)")
      ->check(CLI::Range(0, max_level_set_layers))
      ->capture_default_str();
  command->add_option("--sign", options->sign, "inside/outside by the winding number or the pseudonormal")
      ->check(CLI::IsMember({"winding", "pseudonormal"}))
      ->capture_default_str();
  command->add_flag("--no-cleaning", options->no_cleaning,
                    "keep features thinner than the data spacing (phi stays the exact signed distance)");
  command->add_option("-o,--output", options->output, "folder for the VTK files")->required();
  add_execution_options(*command, options->execution);
  command->callback([options] { run(*options); });
}

}  // namespace unisph::app
