#pragma once
// A free-surface case in a closed rectangular tank: what a case file (TOML) describes.
// Values are in the user's units; nothing assumes g = 1 or rho0 = 1.
//
// The tank's inside is [0, tank[0]] x [0, tank[1]] (x [0, tank[2]]), gravity acts along -y
// (axis 1), and the water column fills [0, column[0]] x [0, column[1]] (x [0, column[2]]).
#include <string>
#include <vector>

namespace unisph::sph {

struct ProbeDescription {
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

struct CaseDescription {
  std::string name;
  std::string source;  // the file it was read from (for messages)
  int dimension = 2;
  // [geometry]
  double dx = 0;
  std::vector<double> tank;
  std::vector<double> column;
  // [fluid]
  double density = 0;             // rho0
  double sound_speed = 0;         // c0
  double reference_velocity = 0;  // U
  double viscosity = 0;           // dynamic viscosity mu
  bool continuity_dissipation = false;  // Riemann velocity dissipation in the continuity equation
  // Density summation where the kernel sum falls short (density_summation.hpp): "reference"
  // (max(rho_sum, rho0)) or "carried" (the shortfall from the carried density added back).
  std::string free_surface_density = "reference";
  // [physics]
  double gravity = 0;  // |g|, acting along -y
  // [initial]
  bool hydrostatic = false;  // start from the hydrostatic pressure and density
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
  // [[probe]]
  std::vector<ProbeDescription> probes;
  // [[obstacle]]
  std::vector<ObstacleDescription> obstacles;
};

}  // namespace unisph::sph
