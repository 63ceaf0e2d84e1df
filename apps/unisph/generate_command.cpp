// `unisph generate GEOMETRY --dx DX [--outside BOX] [--iterations N] [--tolerance T] [--policy ...] -o FILE.vtp`:
// a body-fitted particle set from an STL file (3D) or a .poly polygon file (2D): particles on a
// lattice of spacing DX inside the body (or, with --outside, around it within BOX), relaxed
// against the body's level set (docs/particle_generation.md). Writes
//   FILE.vtp            the particles (position, Volume, NormalDistance = phi at the particle,
//                       Normal = the level set's unit normal there (pointing out of the body),
//                       ZeroOrderError = |Σ ∇W V + G| h, KernelSum, ParticleId) for ParaView, and
//                       as field data Spacing (dx), Dimension and Inside (1: the body's inside,
//                       0: --outside), which `unisph run` checks when a case loads the file as
//                       an obstacle (sph/obstacle_particles.hpp)
//   FILE_residual.csv   iteration, mean and largest zero-order error, step
//   FILE_residual.png   the plot of the CSV (scripts/plot_relaxation.py, when the script and
//                       /usr/bin/python3 with matplotlib are found)
// Every file is written to a temporary name and renamed. Bad input stops with one line on stderr
// before anything is written.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/geometry/geometry_error.hpp"
#include "unisph/geometry/mesh_repair.hpp"
#include "unisph/geometry/polygon_reader.hpp"
#include "unisph/io/vtk_xml_writer.hpp"
#include "unisph/relaxation/particle_relaxation.hpp"
#include "unisph/relaxation/relaxation_level_set.hpp"

namespace unisph::app {

namespace {

struct GenerateOptions {
  std::string file;
  std::string output;
  double dx = 0;
  std::string outside;
  int iterations = 1500;  // RelaxationSettings' default
  double tolerance = 0;
  ExecutionOptions execution;
};

// "--outside x0,y0[,z0],x1,y1[,z1]" -> the box, or an error naming what is wrong.
template <int D>
Box<Real, D> parse_box(const std::string& text) {
  std::vector<double> numbers;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || end == item.c_str() || *end != '\0' || !std::isfinite(v))
      throw Error("--outside: '" + item + "' is not a finite number (expected " + std::to_string(2 * D) +
                  " numbers: the lower corner, then the upper corner, separated by commas)");
    numbers.push_back(v);
  }
  if (numbers.size() != std::size_t(2 * D))
    throw Error("--outside: " + std::to_string(numbers.size()) + " numbers for a " + std::to_string(D) +
                "D geometry; expected " + std::to_string(2 * D) + " (the lower corner, then the upper corner)");
  Box<Real, D> box;
  for (int k = 0; k < D; ++k) {
    box.lower[k] = Real(numbers[k]);
    box.upper[k] = Real(numbers[D + k]);
    if (!(box.lower[k] < box.upper[k]))
      throw Error("--outside: the upper corner must exceed the lower one along axis " + std::to_string(k));
  }
  return box;
}

std::string sibling(const std::string& output, const std::string& suffix) {
  std::filesystem::path p(output);
  return (p.parent_path() / (p.stem().string() + suffix)).string();
}

// The level set's unit normal at each particle (zero where no layer resolves it).
template <int D>
struct ProbeNormal {
  View<const Vec<Real, D>> position;
  View<Vec<Real, D>> normal;
  MultiResolutionLevelSetView<D> level_set;
  UNISPH_HOST_DEVICE void operator()(Index i) const { normal[i] = level_set.probe_normal(position[i]); }
};

template <int D>
void write_particles(const std::string& path, ParticleRelaxation<D>& relaxation, const std::vector<Vec<Real, D>>& normal,
                     double dx, bool inside) {
  const std::vector<Vec<Real, D>> x = relaxation.positions().to_vector(), a = relaxation.residuals().to_vector();
  const std::vector<Real> volume = relaxation.volumes().to_vector(), phi = relaxation.normal_distances().to_vector(),
                          sum = relaxation.kernel_sums().to_vector();
  const std::vector<std::uint64_t> ids = relaxation.body().particles().ids().to_vector();
  std::vector<double> points, volume_out(volume.begin(), volume.end()), phi_out(phi.begin(), phi.end()),
      sum_out(sum.begin(), sum.end()), error(x.size()), normal_out;
  const double half_h = double(relaxation.kernel().h) / 2;  // |a| = 2 |g|, the error is |g| h
  for (std::size_t i = 0; i < x.size(); ++i) {
    for (int k = 0; k < 3; ++k) points.push_back(k < D ? double(x[i][k]) : 0.0);
    error[i] = double(norm(a[i])) * half_h;
    for (int k = 0; k < 3; ++k) normal_out.push_back(k < D ? double(normal[i][k]) : 0.0);
  }
  io::write_vtp(path, points,
                {io::PointArray::from("Volume", 1, volume_out), io::PointArray::from("NormalDistance", 1, phi_out),
                 io::PointArray::from("ZeroOrderError", 1, error), io::PointArray::from("KernelSum", 1, sum_out),
                 io::PointArray::from("Normal", 3, normal_out), io::PointArray::from("ParticleId", 1, ids)},
                {io::PointArray::from("Spacing", 1, std::vector<double>{dx}),
                 io::PointArray::from("Dimension", 1, std::vector<std::int64_t>{D}),
                 io::PointArray::from("Inside", 1, std::vector<std::int64_t>{inside ? 1 : 0})});
}

void write_history(const std::string& path, const std::vector<RelaxationRecord>& history) {
  std::ostringstream csv;
  csv.precision(9);
  csv << "iteration,mean_error,max_error,step\n";
  for (const RelaxationRecord& r : history)
    csv << r.iteration << ',' << double(r.mean_error) << ',' << double(r.max_error) << ',' << double(r.step) << '\n';
  io::write_file_atomically(path, csv.str());
}

void plot_history(const std::string& csv, const std::string& png) {
  const std::filesystem::path script = std::filesystem::path(UNISPH_SOURCE_DIR) / "scripts" / "plot_relaxation.py";
  if (!std::filesystem::exists(script) || !std::filesystem::exists("/usr/bin/python3")) {
    std::printf("  plot   not made (scripts/plot_relaxation.py or /usr/bin/python3 not found); run\n"
                "         /usr/bin/python3 scripts/plot_relaxation.py %s %s\n", csv.c_str(), png.c_str());
    return;
  }
  const std::string command = "/usr/bin/python3 '" + script.string() + "' '" + csv + "' '" + png + "'";
  if (std::system(command.c_str()) != 0)
    std::printf("  plot   failed (%s)\n", command.c_str());
  else
    std::printf("  wrote  %s\n", png.c_str());
}

template <int D, class Search>
void generate(Search& search, const Box<Real, D>& shape_box, double enclosed, const GenerateOptions& options) {
  const bool outside = !options.outside.empty();
  const Box<Real, D> region = outside ? parse_box<D>(options.outside) : shape_box;
  Box<Real, D> covered = region;
  for (int k = 0; k < D; ++k) {
    covered.lower[k] = std::min(covered.lower[k], shape_box.lower[k]);
    covered.upper[k] = std::max(covered.upper[k], shape_box.upper[k]);
  }
  const Real dx = Real(options.dx);
  visit_policy(parse_policy(options.execution.policy), [&](auto policy) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    std::unique_ptr<MultiResolutionLevelSet<D>> level_set = make_relaxation_level_set<D>(policy, search, covered, dx);
    fence(policy);
    const auto t1 = Clock::now();
    ParticleRelaxation<D> relaxation(policy, *level_set, region, outside ? SeedRegion::outside : SeedRegion::inside,
                                     dx, WindingNumberSide<ShapeSearchView<D>>{search.view(policy), !outside});
    fence(policy);
    const auto t2 = Clock::now();
    std::printf("%s: %dD, dx %.6g, %zu particles %s, policy %s\n", options.file.c_str(), D, options.dx,
                relaxation.size(), outside ? "around the body in the box" : "inside the body",
                options.execution.policy.c_str());
    std::printf("  level set %.3f s (%d layers), lattice %.3f s\n", std::chrono::duration<double>(t1 - t0).count(),
                level_set->levels(), std::chrono::duration<double>(t2 - t1).count());
    if (!outside && enclosed > 0)
      std::printf("  particle volume %.6g, enclosed by the geometry %.6g (%+.3f %%)\n",
                  double(relaxation.size()) * std::pow(options.dx, D), enclosed,
                  100 * (double(relaxation.size()) * std::pow(options.dx, D) / enclosed - 1));
    RelaxationSettings settings;
    settings.iterations = options.iterations;
    settings.tolerance = Real(options.tolerance);
    const int every = std::max(1, options.iterations / 20);
    const auto t3 = Clock::now();
    const std::vector<RelaxationRecord> history = relaxation.run(policy, settings, [&](const RelaxationRecord& r) {
      if (r.iteration % every == 0 || r.step == Real(0))
        std::printf("  iteration %6d  zero-order error mean %.3e  max %.3e\n", r.iteration, double(r.mean_error),
                    double(r.max_error));
      std::fflush(stdout);
    });
    const double seconds = std::chrono::duration<double>(Clock::now() - t3).count();
    const int iterations = history.back().iteration;
    std::printf("  relaxation %d iterations in %.3f s (%.3f us per particle and iteration); error mean %.1fx and max "
                "%.1fx below the lattice's\n",
                iterations, seconds, iterations > 0 ? 1e6 * seconds / (double(iterations) * double(relaxation.size())) : 0.0,
                double(history.front().mean_error / history.back().mean_error),
                double(history.front().max_error / history.back().max_error));
    relaxation.surface_distances(policy);
    DiscreteVariable<Vec<Real, D>> normal("Normal", relaxation.size());
    particle_for(policy, relaxation.size(),
                 ProbeNormal<D>{relaxation.positions().read(policy), normal.write(policy), level_set->view(policy)});
    write_particles<D>(options.output, relaxation, normal.to_vector(), options.dx, !outside);
    std::printf("  wrote  %s\n", options.output.c_str());
    const std::string csv = sibling(options.output, "_residual.csv");
    write_history(csv, history);
    std::printf("  wrote  %s\n", csv.c_str());
    plot_history(csv, sibling(options.output, "_residual.png"));
  });
}

bool is_polygon_file(const std::string& file) {
  return file.size() >= 5 && file.compare(file.size() - 5, 5, ".poly") == 0;
}

void run(const GenerateOptions& options) {
  require_policy(parse_policy(options.execution.policy));  // before anything is read or written
  if (std::filesystem::path(options.output).extension() != ".vtp")
    throw Error("-o " + options.output + ": the particle file must end in .vtp (VTK PolyData)");
  if (is_polygon_file(options.file)) {
    const LoadedPolygons loaded = read_polygons(options.file);
    if (loaded.polygons.empty())
      throw GeometryError(options.file + ": the file has no loops; particle generation needs at least one");
    if (!options.outside.empty()) parse_box<2>(options.outside);
    PolygonSearch search(loaded.polygons);
    Box<Real, 2> box;
    for (int k = 0; k < 2; ++k) box.lower[k] = Real(loaded.report.box_min[k]), box.upper[k] = Real(loaded.report.box_max[k]);
    generate<2>(search, box, loaded.report.area, options);
  } else {
    const LoadedMesh loaded = load_triangle_mesh(options.file);
    require_triangles(loaded.mesh, "particle generation");
    if (!options.outside.empty()) parse_box<3>(options.outside);
    TriangleMeshSearch search(loaded.mesh);
    Box<Real, 3> box;
    for (int k = 0; k < 3; ++k) box.lower[k] = Real(loaded.report.box_min[k]), box.upper[k] = Real(loaded.report.box_max[k]);
    generate<3>(search, box, loaded.report.closed() ? loaded.report.divergence_volume : 0.0, options);
  }
}

}  // namespace

void add_generate_command(CLI::App& app) {
  auto options = std::make_shared<GenerateOptions>();
  CLI::App* command = app.add_subcommand(
      "generate", "make a body-fitted particle set from an STL file (or a .poly polygon file): lattice seeding, then "
                  "relaxation against the level set; writes the particles (.vtp) and the residual history (.csv, .png)");
  command->add_option("file", options->file, "the STL file (binary or ASCII), or closed polygons in a .poly text file")
      ->required();
  command->add_option("--dx", options->dx, "particle spacing (also the level set's finest spacing)")
      ->required()
      ->check(CLI::PositiveNumber);
  command->add_option("--outside", options->outside,
                      "fill the box x0,y0[,z0],x1,y1[,z1] around the body instead of the body itself");
  command->add_option("--iterations", options->iterations, "relaxation iterations at most")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  command->add_option("--tolerance", options->tolerance,
                      "stop earlier once the mean zero-order error |sum grad W V + G| h is below (0: never)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  command->add_option("-o,--output", options->output, "the particle file (.vtp); the history goes next to it")
      ->required();
  add_execution_options(*command, options->execution);
  command->callback([options] { run(*options); });
}

}  // namespace unisph::app
