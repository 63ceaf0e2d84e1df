// Writing and reading the case and the summary of a solver checkpoint (the particle data are
// written by the solver itself, weakly_compressible_solver_impl.hpp).
#include "unisph/solver/solver_checkpoint.hpp"

#include <sstream>
#include <tuple>

namespace unisph::sph {

namespace {
void write_motion(io::CheckpointWriter& out, const MotionDescription& m) {
  out.string(m.law);
  out.f64s(m.direction);
  out.f64s(m.pivot);
  out.f64s(m.axis);
  for (double v : {m.rate, m.amplitude, m.period, m.phase, m.ramp_periods, m.start}) out.f64(v);
  out.string(m.file);
  out.u32(std::uint32_t(m.line));
}
MotionDescription read_motion(io::CheckpointReader& in) {
  MotionDescription m;
  m.law = in.string();
  m.direction = in.f64s();
  m.pivot = in.f64s();
  m.axis = in.f64s();
  for (double* v : {&m.rate, &m.amplitude, &m.period, &m.phase, &m.ramp_periods, &m.start}) *v = in.f64();
  m.file = in.string();
  m.line = int(in.u32());
  return m;
}
// The length of a list in the case section, bounded so that a damaged file cannot ask for
// billions of entries.
std::uint64_t read_count(io::CheckpointReader& in, const char* what) {
  const std::uint64_t n = in.u64();
  if (n > 100000) in.fail("holds " + std::to_string(n) + " " + what + " (damaged case section)");
  return n;
}
}  // namespace

void write_case(io::CheckpointWriter& out, const CaseDescription& c) {
  out.section("case");
  out.string(c.name);
  out.string(c.source);
  out.u32(std::uint32_t(c.dimension));
  out.f64(c.dx);
  out.f64s(c.tank);
  out.f64s(c.column);
  out.f64(c.density);
  out.f64(c.sound_speed);
  out.f64(c.reference_velocity);
  out.f64(c.viscosity);
  out.u32(c.continuity_dissipation ? 1 : 0);
  out.string(c.free_surface_density);
  out.string(c.density_method);
  out.f64(c.density_diffusion);
  out.string(c.wall_continuity);
  out.string(c.wall_pressure);
  out.f64(c.gravity);
  out.u32(c.hydrostatic ? 1 : 0);
  out.f64(c.settling_time);
  out.f64(c.settling_damping);
  out.f64(c.end_time);
  out.f64(c.output_interval);
  out.u32(std::uint32_t(c.sort_every));
  out.f64(c.checkpoint_every);
  out.string(c.neighbor_search);
  out.u32(std::uint32_t(c.cells_per_cutoff));
  out.string(c.last_acoustic_step);
  out.f64(c.length_scale);
  out.f64(c.time_scale);
  out.f64(c.pressure_scale);
  out.u32(c.loads ? 1 : 0);
  out.f64s(c.moment_point);
  out.u64(c.probes.size());
  for (const ProbeDescription& p : c.probes) {
    out.string(p.name);
    out.f64s(p.position);
    out.f64(p.kernel_width);
  }
  out.f64s(c.damping_zone.direction);
  out.f64(c.damping_zone.start);
  out.f64(c.damping_zone.end);
  out.f64(c.damping_zone.strength);
  out.string(c.damping_zone.form);
  out.u64(c.velocity_probes.size());
  for (const VelocityProbeDescription& p : c.velocity_probes) {
    out.string(p.name);
    out.f64s(p.position);
  }
  out.u64(c.gauges.size());
  for (const GaugeDescription& g : c.gauges) {
    out.string(g.name);
    out.f64s(g.position);
    out.f64(g.bottom);
    out.f64(g.top);
    out.u32(std::uint32_t(g.line));
  }
  out.u64(c.obstacles.size());
  for (const ObstacleDescription& o : c.obstacles) {
    out.string(o.file);
    out.f64s(o.translation);
    out.u32(std::uint32_t(o.line));
  }
  out.f64s(c.gravity_vector);
  out.f64(c.free_surface);
  out.f64s(c.domain.lower);
  out.f64s(c.domain.upper);
  out.string(c.domain.leaving);
  out.u64(c.domain.periodic.size());
  for (int a : c.domain.periodic) out.u32(std::uint32_t(a));
  out.u32(std::uint32_t(c.domain.periodic_line));
  out.u64(c.shapes.size());
  for (const ShapeDescription& s : c.shapes) {
    out.string(s.name);
    out.string(s.type);
    out.u64(s.values.size());
    for (const auto& [key, value] : s.values) {
      out.string(key);
      out.f64s(value);
    }
    out.u64(s.operands.size());
    for (const std::string& o : s.operands) out.string(o);
    out.string(s.file);
    out.u32(std::uint32_t(s.line));
  }
  out.u64(c.bodies.size());
  for (const BodyDescription& b : c.bodies) {
    out.string(b.name);
    out.string(b.kind);
    out.string(b.shape);
    out.f64s(b.velocity);
    out.u32(std::uint32_t(b.layers));
    out.u32(std::uint32_t(b.line));
    write_motion(out, b.translation);
    write_motion(out, b.rotation);
  }
}

CaseDescription read_case(io::CheckpointReader& in) {
  in.section("case");
  CaseDescription c;
  c.name = in.string();
  c.source = in.string();
  c.dimension = int(in.u32());
  c.dx = in.f64();
  c.tank = in.f64s();
  c.column = in.f64s();
  c.density = in.f64();
  c.sound_speed = in.f64();
  c.reference_velocity = in.f64();
  c.viscosity = in.f64();
  c.continuity_dissipation = in.u32() != 0;
  c.free_surface_density = in.string();
  c.density_method = in.string();
  c.density_diffusion = in.f64();
  c.wall_continuity = in.string();
  c.wall_pressure = in.string();
  c.gravity = in.f64();
  c.hydrostatic = in.u32() != 0;
  c.settling_time = in.f64();
  c.settling_damping = in.f64();
  c.end_time = in.f64();
  c.output_interval = in.f64();
  c.sort_every = int(in.u32());
  c.checkpoint_every = in.f64();
  c.neighbor_search = in.string();
  c.cells_per_cutoff = int(in.u32());
  c.last_acoustic_step = in.string();
  c.length_scale = in.f64();
  c.time_scale = in.f64();
  c.pressure_scale = in.f64();
  c.loads = in.u32() != 0;
  c.moment_point = in.f64s();
  const std::uint64_t probes = read_count(in, "probes");
  for (std::uint64_t k = 0; k < probes; ++k) {
    ProbeDescription p;
    p.name = in.string();
    p.position = in.f64s();
    p.kernel_width = in.f64();
    c.probes.push_back(p);
  }
  c.damping_zone.direction = in.f64s();
  c.damping_zone.start = in.f64();
  c.damping_zone.end = in.f64();
  c.damping_zone.strength = in.f64();
  c.damping_zone.form = in.string();
  const std::uint64_t velocity_probes = read_count(in, "velocity probes");
  for (std::uint64_t k = 0; k < velocity_probes; ++k) {
    VelocityProbeDescription p;
    p.name = in.string();
    p.position = in.f64s();
    c.velocity_probes.push_back(p);
  }
  const std::uint64_t gauges = read_count(in, "gauges");
  for (std::uint64_t k = 0; k < gauges; ++k) {
    GaugeDescription g;
    g.name = in.string();
    g.position = in.f64s();
    g.bottom = in.f64();
    g.top = in.f64();
    g.line = int(in.u32());
    c.gauges.push_back(g);
  }
  const std::uint64_t obstacles = read_count(in, "obstacles");
  for (std::uint64_t k = 0; k < obstacles; ++k) {
    ObstacleDescription o;
    o.file = in.string();
    o.translation = in.f64s();
    o.line = int(in.u32());
    if (int(o.translation.size()) != c.dimension) in.fail("holds an obstacle whose translation is not one value per axis");
    c.obstacles.push_back(o);
  }
  c.gravity_vector = in.f64s();
  c.free_surface = in.f64();
  c.domain.lower = in.f64s();
  c.domain.upper = in.f64s();
  c.domain.leaving = in.string();
  const std::uint64_t periodic = in.u64();
  if (periodic > std::uint64_t(c.dimension)) in.fail("holds " + std::to_string(periodic) + " periodic axes (damaged case section)");
  for (std::uint64_t k = 0; k < periodic; ++k) {
    const std::uint32_t a = in.u32();
    if (a >= std::uint32_t(c.dimension)) in.fail("holds periodic axis " + std::to_string(a) + " (damaged case section)");
    c.domain.periodic.push_back(int(a));
  }
  c.domain.periodic_line = int(in.u32());
  const std::uint64_t shapes = read_count(in, "shapes");
  for (std::uint64_t k = 0; k < shapes; ++k) {
    ShapeDescription s;
    s.name = in.string();
    s.type = in.string();
    const std::uint64_t values = in.u64();
    if (values > 64) in.fail("holds a shape with " + std::to_string(values) + " values (damaged case section)");
    for (std::uint64_t v = 0; v < values; ++v) {
      std::string key = in.string();
      s.values.emplace_back(std::move(key), in.f64s());
    }
    const std::uint64_t operands = in.u64();
    if (operands > 100000) in.fail("holds a shape with " + std::to_string(operands) + " operands (damaged case section)");
    for (std::uint64_t o = 0; o < operands; ++o) s.operands.push_back(in.string());
    s.file = in.string();
    s.line = int(in.u32());
    c.shapes.push_back(std::move(s));
  }
  const std::uint64_t bodies = read_count(in, "bodies");
  for (std::uint64_t k = 0; k < bodies; ++k) {
    BodyDescription b;
    b.name = in.string();
    b.kind = in.string();
    b.shape = in.string();
    b.velocity = in.f64s();
    b.layers = int(in.u32());
    b.line = int(in.u32());
    b.translation = read_motion(in);
    b.rotation = read_motion(in);
    c.bodies.push_back(std::move(b));
  }
  if (c.dimension != 2 && c.dimension != 3) in.fail("holds a case of dimension " + std::to_string(c.dimension));
  const bool shape_ok = c.general() || (int(c.tank.size()) == c.dimension && int(c.column.size()) == c.dimension);
  if (!shape_ok || !(c.dx > 0) || c.sort_every < 1)
    in.fail("holds a case section that is not a valid case (tank, column, dx or sort interval)");
  return c;
}

namespace {
std::string text(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}
std::string text(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + text(v[i]);
  return s + "]";
}
std::string text(bool v) { return v ? "true" : "false"; }
std::string text(const std::string& v) { return "\"" + v + "\""; }
std::string text(int v) { return std::to_string(v); }
}  // namespace

std::string physics_difference(const CaseDescription& a, const CaseDescription& b) {
  std::string found;
  auto field = [&](const std::string& name, const auto& x, const auto& y) {
    if (found.empty() && !(x == y)) found = std::string(name) + " (" + text(x) + " here, " + text(y) + " in the checkpoint)";
  };
  field("dimension", a.dimension, b.dimension);
  field("geometry.dx", a.dx, b.dx);
  field("geometry.tank", a.tank, b.tank);
  field("geometry.column", a.column, b.column);
  field("fluid.density", a.density, b.density);
  field("fluid.sound_speed", a.sound_speed, b.sound_speed);
  field("fluid.reference_velocity", a.reference_velocity, b.reference_velocity);
  field("fluid.viscosity", a.viscosity, b.viscosity);
  field("fluid.continuity_dissipation", a.continuity_dissipation, b.continuity_dissipation);
  field("fluid.free_surface_density", a.free_surface_density, b.free_surface_density);
  field("fluid.density_method", a.density_method, b.density_method);
  field("fluid.density_diffusion", a.density_diffusion, b.density_diffusion);
  field("fluid.wall_continuity", a.wall_continuity, b.wall_continuity);
  field("fluid.wall_pressure", a.wall_pressure, b.wall_pressure);
  field("physics.gravity", a.gravity, b.gravity);
  field("initial.state is hydrostatic", a.hydrostatic, b.hydrostatic);
  field("time.sort_every", a.sort_every, b.sort_every);
  field("time.neighbor_search", a.neighbor_search, b.neighbor_search);
  field("time.cells_per_cutoff", a.cells_per_cutoff, b.cells_per_cutoff);
  field("time.last_acoustic_step", a.last_acoustic_step, b.last_acoustic_step);
  field("number of probes", int(a.probes.size()), int(b.probes.size()));
  for (std::size_t k = 0; k < a.probes.size() && k < b.probes.size(); ++k)
    field("probe.position", a.probes[k].position, b.probes[k].position);
  field("damping_zone.direction", a.damping_zone.direction, b.damping_zone.direction);
  field("damping_zone.start", a.damping_zone.start, b.damping_zone.start);
  field("damping_zone.end", a.damping_zone.end, b.damping_zone.end);
  field("damping_zone.strength", a.damping_zone.strength, b.damping_zone.strength);
  field("damping_zone.form", a.damping_zone.form, b.damping_zone.form);
  field("number of velocity probes", int(a.velocity_probes.size()), int(b.velocity_probes.size()));
  for (std::size_t k = 0; k < a.velocity_probes.size() && k < b.velocity_probes.size(); ++k)
    field("velocity_probe.position", a.velocity_probes[k].position, b.velocity_probes[k].position);
  field("number of obstacles", int(a.obstacles.size()), int(b.obstacles.size()));
  for (std::size_t k = 0; k < a.obstacles.size() && k < b.obstacles.size(); ++k) {
    field("obstacle.file", a.obstacles[k].file, b.obstacles[k].file);
    field("obstacle.translation", a.obstacles[k].translation, b.obstacles[k].translation);
  }
  field("physics.gravity (vector)", a.gravity_vector, b.gravity_vector);
  field("initial.free_surface", a.free_surface, b.free_surface);
  field("domain.lower", a.domain.lower, b.domain.lower);
  field("domain.upper", a.domain.upper, b.domain.upper);
  field("domain.leaving", a.domain.leaving, b.domain.leaving);
  {
    std::vector<double> x(a.domain.periodic.begin(), a.domain.periodic.end()), y(b.domain.periodic.begin(), b.domain.periodic.end());
    field("domain.periodic (axes)", x, y);
  }
  field("number of shapes", int(a.shapes.size()), int(b.shapes.size()));
  for (std::size_t k = 0; k < a.shapes.size() && k < b.shapes.size(); ++k) {
    const ShapeDescription &x = a.shapes[k], &y = b.shapes[k];
    field("shape.name", x.name, y.name);
    field("shape.type", x.type, y.type);
    field("shape.file", x.file, y.file);
    field("number of values of a shape", int(x.values.size()), int(y.values.size()));
    for (std::size_t v = 0; v < x.values.size() && v < y.values.size(); ++v) {
      field("a shape's key", x.values[v].first, y.values[v].first);
      field(("shape." + x.values[v].first).c_str(), x.values[v].second, y.values[v].second);
    }
    field("number of operands of a shape", int(x.operands.size()), int(y.operands.size()));
    for (std::size_t o = 0; o < x.operands.size() && o < y.operands.size(); ++o) field("shape.shapes", x.operands[o], y.operands[o]);
  }
  field("number of bodies", int(a.bodies.size()), int(b.bodies.size()));
  for (std::size_t k = 0; k < a.bodies.size() && k < b.bodies.size(); ++k) {
    const BodyDescription &x = a.bodies[k], &y = b.bodies[k];
    field("body.name", x.name, y.name);
    field("body.kind", x.kind, y.kind);
    field("body.shape", x.shape, y.shape);
    field("body.velocity", x.velocity, y.velocity);
    field("body.layers", x.layers, y.layers);
    for (const auto& [key, p, q] : {std::tuple{"body.translation", &x.translation, &y.translation},
                                    std::tuple{"body.rotation", &x.rotation, &y.rotation}}) {
      const std::string k(key);
      field(k + ".law", p->law, q->law);
      field(k + ".direction", p->direction, q->direction);
      field(k + ".pivot", p->pivot, q->pivot);
      field(k + ".axis", p->axis, q->axis);
      field(k + ".velocity or rate", p->rate, q->rate);
      field(k + ".amplitude", p->amplitude, q->amplitude);
      field(k + ".period", p->period, q->period);
      field(k + ".phase", p->phase, q->phase);
      field(k + ".ramp_periods", p->ramp_periods, q->ramp_periods);
      field(k + ".start", p->start, q->start);
      field(k + ".file", p->file, q->file);
    }
  }
  return found;
}

CheckpointSummary read_checkpoint_summary(const std::filesystem::path& path) {
  io::CheckpointReader in(path, solver_checkpoint_version);
  CheckpointSummary s;
  in.section("run");
  s.dimension = int(in.u32());
  const std::uint32_t bytes = in.u32();
  s.precision = in.string();
  if ((s.dimension != 2 && s.dimension != 3) || !((bytes == 4 && s.precision == "float") || (bytes == 8 && s.precision == "double")))
    in.fail("holds an unknown run (dimension " + std::to_string(s.dimension) + ", precision '" + s.precision + "')");
  s.description = read_case(in);
  if (s.description.dimension != s.dimension) in.fail("holds a case whose dimension differs from its run's");
  in.section("time");
  s.time = in.f64();
  s.advection_steps = in.u64();
  s.acoustic_steps = in.u64();
  return s;
}

}  // namespace unisph::sph
