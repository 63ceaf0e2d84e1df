#pragma once
// A free-surface case: what a case file (TOML) describes, and what a C++ program fills to run
// its own case (examples/02_general_case.cpp). Values are in the user's units; nothing assumes
// g = 1 or rho0 = 1.
//
// Two ways to describe the bodies:
//  * the short form: a closed rectangular tank whose inside is [0, tank[0]] x [0, tank[1]]
//    (x [0, tank[2]]) and a water column filling [0, column[0]] x [0, column[1]] (x ...) from the
//    corner, gravity along -y; the tank's walls keep their own layout (tank_particles.hpp), so a
//    short-form case gives the particles, and so the results, of earlier versions;
//  * the general form: named shapes ([[shape]]) and bodies made of them ([[body]]): any number of
//    fluid bodies (one fluid) and of wall bodies, in a domain that need not be closed by walls,
//    with gravity along any vector.
#include <functional>
#include <string>
#include <vector>

namespace unisph::sph {

struct ProbeDescription {
  std::string name;
  std::vector<double> position;
  // The probe's smoothing length as a multiple of the fluid's (h = 1.3 dx): a wider kernel
  // averages the pressure over more particles, as a sensor of finite size does.
  // TrixiParticles' dam-break sensors interpolate with twice its h = 2 dx, i.e. 3.08 of ours.
  double kernel_width = 1;
};

// [[gauge]]: a wave gauge (sph/wave_gauge.hpp): the free-surface elevation on the line through
// `position` along -gravity, between the levels `bottom` and `top` (measured along -gravity).
struct GaugeDescription {
  std::string name;
  std::vector<double> position;
  double bottom = 0, top = 0;
  int line = 0;
};

// [damping_zone]: passive wave absorption (sph/damping_zone.hpp): the fluid's velocity relaxed
// towards zero at the rate strength xi^2, xi = 0 ... 1 from `start` to `end` along `direction`.
struct DampingZoneDescription {
  std::vector<double> direction;  // empty: no zone
  double start = 0, end = 0, strength = 0;
  std::string form = "linear";  // or "exponential"
  bool present() const { return !direction.empty(); }
};

// [[velocity_probe]]: the fluid's kernel-averaged velocity at a point (sph/velocity_probe.hpp),
// written as velocity_<name>_x, _y(, _z) in observers.csv.
struct VelocityProbeDescription {
  std::string name;
  std::vector<double> position;
};

// A static body from a particle file of `unisph generate` (sph/obstacle_particles.hpp):
// [[obstacle]] file = "cylinder.vtp" (relative to the case file), translation = [x, y(, z)].
struct ObstacleDescription {
  std::string file;                 // as resolved: the case file's folder / the file named
  std::vector<double> translation;  // D values (zeros by default)
  int line = 0;                     // of its `file` key in the case file, for messages
};

// [[shape]]: a named shape (shape/shape.hpp). `type` is one of box, sphere (a circle in 2D),
// cylinder (3D), half_space, polygon (2D file), mesh (3D STL file), union, intersection,
// difference, shell; every numeric key it takes is in `values` by name (lower, upper, center,
// radius, start, end, point, normal, thickness), the shapes it combines in `operands`, and the
// optional rigid transform in scale, rotation (angle in degrees, axis in 3D, about `pivot`) and
// translation, applied in that order.
struct ShapeDescription {
  std::string name;
  std::string type;
  std::vector<std::pair<std::string, std::vector<double>>> values;
  std::vector<std::string> operands;
  std::string file;  // polygon, mesh: as resolved (the case file's folder / the file named)
  int line = 0;      // of its [[shape]] table in the case file, for messages

  const std::vector<double>* value(const std::string& key) const {
    for (const auto& [k, v] : values)
      if (k == key) return &v;
    return nullptr;
  }
};

// [body.translation] / [body.rotation] of a wall body: a prescribed motion (motion/time_law.hpp,
// motion/rigid_motion.hpp). `law` is empty (no such motion), "constant", "sinusoid" or "table".
// Translation: along `direction` (D numbers), by velocity t ("constant"), by
// amplitude sin(2 pi (t - start) / period + phase) ramped over ramp_periods periods
// ("sinusoid"), or by the displacement of a CSV table time,displacement ("table", `file`).
// Rotation: about `pivot` (D numbers; in 3D about `axis`), the angle in degrees: rate t,
// the sinusoid of amplitude degrees, or a table time,angle in degrees. Phases in degrees.
struct MotionDescription {
  std::string law;
  std::vector<double> direction;  // translation
  std::vector<double> pivot, axis;  // rotation (axis: 3D only)
  double rate = 0;                 // "constant": velocity, or degrees per unit time
  double amplitude = 0, period = 0, phase = 0, ramp_periods = 0, start = 0;  // "sinusoid"
  std::string file;                // "table": as resolved (the case file's folder / the file named)
  int line = 0;                    // of the table [body.translation] / [body.rotation], for messages

  bool moves() const { return !law.empty(); }
};

// [[body]]: particles made from a shape. A fluid body fills its shape on the lattice
// x = (i + 1/2) dx; a wall body is the dummy particles of its shape's solid side, `layers`
// lattice layers deep, with normals out of the solid. With fill = "relaxed" the particles are
// body-fitted instead: seeded on the lattice, then relaxed against the shape's surface
// (shape/relaxed_particles.hpp); a relaxed fluid fills its shape less the walls'.
struct BodyDescription {
  std::string name;
  std::string kind;                // "fluid" or "wall"
  std::string shape;               // the name of a [[shape]]
  std::vector<double> velocity;    // fluid: initial velocity (D values, zeros by default)
  int layers = 4;                  // wall: layers of dummy particles (lattice layers, or the band's depth in dx)
  int line = 0;
  std::string fill = "lattice";    // "lattice" or "relaxed"
  int relaxation_iterations = 1500;  // fill = "relaxed": iterations of the relaxation
  MotionDescription translation, rotation;  // wall: a prescribed motion (none by default)

  bool moves() const { return translation.moves() || rotation.moves(); }
};

// [domain]: the box particles live in. A fluid particle that leaves it is removed and counted
// ("remove", the default of the general form) or stops the run with a diagnostic ("stop", the
// short form's default).
//
// Periodic axes (domain.periodic = ["x", "y"]; general form only): a fluid particle that crosses
// a periodic face comes back in through the opposite one (it is wrapped, never removed: `leaving`
// applies to the other axes), and sees its neighbours across the face through ghost images
// (neighbor/periodic_images.hpp; docs/sph.md, "Periodic axes"). A wall along a periodic axis
// (a plate of a channel) must run through both periodic faces; it gets images too.
struct DomainDescription {
  std::vector<double> lower, upper;  // D values each; empty: the tank's box with its walls
  std::string leaving = "stop";
  std::vector<int> periodic;  // the periodic axes (0 = x, 1 = y, 2 = z), ascending; empty: none
  int periodic_line = 0;      // of the `periodic` key in the case file, for messages

  bool is_periodic(int axis) const {
    for (int a : periodic)
      if (a == axis) return true;
    return false;
  }
};

// C++ only (the case file cannot express it): the initial state of each fluid particle from its
// position x (D values). `velocity` (D values) comes in as the body's velocity and `pressure` as
// the hydrostatic or zero start; the function may change both. The density follows from the
// pressure through the equation of state. Called once per fluid particle on the host when the
// solver is made (not on a restore: the checkpoint holds the state), in the particles' order.
using InitialFluidState = std::function<void(const std::vector<double>& x, std::vector<double>& velocity, double& pressure)>;

struct CaseDescription {
  std::string name;
  std::string source;  // the file it was read from (for messages)
  int dimension = 2;
  // [geometry]
  double dx = 0;
  // h / dx of the fluid's kernel (the Wendland C2 kernel's cutoff is 2 h). Wall bodies need
  // layers >= 2 h/dx + 0.5 (the short form's tank and obstacles have 4: h <= 1.75 dx).
  double smoothing_length_ratio = 1.3;
  std::vector<double> tank;
  std::vector<double> column;
  // [fluid]
  double density = 0;             // rho0
  double sound_speed = 0;         // c0
  double reference_velocity = 0;  // U
  double viscosity = 0;           // dynamic viscosity mu
  bool continuity_dissipation = false;  // Riemann velocity dissipation in the continuity equation
  // The pressure gradient corrected by each particle's kernel moment (CorrectedPressureRelaxation):
  // right free-surface waves (docs/validation.md); off by default, as the validated dam breaks run.
  bool kernel_gradient_correction = false;
  // Density summation where the kernel sum falls short (density_summation.hpp): "reference"
  // (max(rho_sum, rho0)) or "carried" (the shortfall from the carried density added back), or
  // "none" (rho_sum as it is: a flow without free surface, such as a periodic box).
  std::string free_surface_density = "reference";
  // Where the density comes from (docs/sph.md, "Density"): "summation" (the kernel sum at every
  // advection step, the continuity equation within it: SPHinXsys' scheme) or "continuity" (the
  // continuity equation alone, as delta-SPH, DualSPHysics and TrixiParticles do).
  std::string density_method = "summation";
  // The continuity equation's term of a wall dummy particle (density_relaxation.hpp): "mirror"
  // (the fluid particle's normal velocity mirrored, 2 (v_i - v_w).n (n.e_iw)) or "kernel_sum"
  // ((v_i - v_w).e_iw: the rate of the kernel sum over the wall particles that the density
  // summation counts; docs/validation.md, "The continuity equation's wall term").
  std::string wall_continuity = "mirror";
  // The wall dummy particles' pressure (wall_dummy_pressure.hpp, wall_pressure_average.hpp):
  // "extrapolated" (each pair extrapolates the fluid particle's own pressure hydrostatically to the
  // wall particle, SPHinXsys' form) or "averaged" (each wall particle's own, a kernel average over
  // its fluid neighbours: Adami et al. 2012, as TrixiParticles; one rank, no periodic axis).
  std::string wall_pressure = "extrapolated";
  // delta of delta-SPH's density-diffusion term (sph/density_diffusion.hpp); 0: none.
  double density_diffusion = 0;
  // A of the particle shifting dr = -A h^2 grad C once per advection step (sph/particle_shifting.hpp);
  // 0: none.
  double particle_shifting = 0;
  // [physics]
  double gravity = 0;                  // |g|
  std::vector<double> gravity_vector;  // g itself (D values): (0, -gravity(, 0)) in the short form
  // [domain]
  DomainDescription domain;
  // [[shape]], [[body]] (the general form; empty in the short form)
  std::vector<ShapeDescription> shapes;
  std::vector<BodyDescription> bodies;
  // [initial]
  // C++ only: a per-particle initial velocity and pressure (above); not stored in checkpoints.
  InitialFluidState initial_fluid_state;
  bool hydrostatic = false;  // start from the hydrostatic pressure and density
  // The free surface's level for the hydrostatic start, measured along -g (the height, for
  // gravity along -y); the short form takes the column's height.
  double free_surface = 0;
  // Settling before time 0 (docs/sph.md, "Settling"): the water moves under the case's forces
  // with its velocity damped at `settling_damping` (1/time) for `settling_time`, then starts
  // from where it came to rest, at rest. 0: no settling.
  double settling_time = 0;
  double settling_damping = 0;
  // [time]
  double end_time = 0;
  double output_interval = 0;
  int sort_every = 1;  // advection steps between particle sorts
  double checkpoint_every = 0;  // simulated time between checkpoints of `unisph run` (0: none)
  // Neighbour search of the fluid relations: "automatic" (stored lists on the CPU, direct
  // search on the GPU, see docs/neighbor_search.md), "stored" or "direct".
  std::string neighbor_search = "automatic";
  // The last acoustic step of an advection step: "shortened" so that the advection step ends at
  // Dt exactly, or "full" (every acoustic step of the CFL size; the advection step ends with the
  // first one that reaches Dt, passing it by less than one acoustic step: SPHinXsys' loop, about
  // 12 % fewer acoustic steps in the dam break). Steps that end at an output time are shortened
  // in both.
  std::string last_acoustic_step = "shortened";
  // Cells of the neighbour search per cutoff: 1 (cells of the cutoff, a 3^D stencil), 2 (cells
  // of half the cutoff, a 5^D stencil with the rows beyond the cutoff skipped: fewer candidates,
  // more cells), 0: automatic (2 on the GPU, 1 on the CPU; measured in docs/sph.md).
  int cells_per_cutoff = 0;
  // [report]: reference scales for the dimensionless columns of the observer file
  double length_scale = 1;
  double time_scale = 1;
  double pressure_scale = 1;
  // report.loads: every wall body's force and moment about moment_point (D values), the mean over
  // each advection step's acoustic steps, to loads.csv (solver: loads()).
  bool loads = false;
  std::vector<double> moment_point;
  // [[probe]]
  std::vector<ProbeDescription> probes;
  // [[velocity_probe]]
  std::vector<VelocityProbeDescription> velocity_probes;
  // [damping_zone]
  DampingZoneDescription damping_zone;
  // [[gauge]]
  std::vector<GaugeDescription> gauges;
  // [[obstacle]]
  std::vector<ObstacleDescription> obstacles;

  bool general() const { return !bodies.empty(); }
  // A wall body has a prescribed motion ([body.translation] or [body.rotation]).
  bool walls_move() const {
    for (const BodyDescription& b : bodies)
      if (b.kind == "wall" && b.moves()) return true;
    return false;
  }
};

}  // namespace unisph::sph
