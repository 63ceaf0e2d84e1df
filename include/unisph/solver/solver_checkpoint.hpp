#pragma once
// The layout of a solver checkpoint inside the checkpoint container (io/checkpoint_file.hpp),
// format version 7:
//
//   "run"        dimension (u32), bytes of the floating type (u32), "float" or "double"
//   "case"       every field of the CaseDescription (obstacles: resolved file, translation, line)
//   "time"       time (f64), advection steps (u64), acoustic steps (u64), phase (u32): 0, the
//                only phase a checkpoint is taken in, is "after an advection step, particles
//                sorted when due, neighbour structures to be rebuilt from the positions"; fluid
//                particles removed for leaving the domain (u64) and their mass (f64)
//   "body" x 2   fluid, then wall (the wall bodies' particles in turn): name, owned particles (u64), first id (u64), then each
//                sortable variable (ids included): name, type, element size (u64), bytes
//   "observers"  the caller's run state (e.g. `unisph run`'s output counters): one block
//
// The neighbour structures (cell lists, stored lists) are not stored: they are functions of
// the positions and their order, rebuilt on restore as after any advection step.
#include <cstdint>
#include <filesystem>
#include <string>

#include "unisph/io/checkpoint_file.hpp"
#include "unisph/solver/case_description.hpp"

namespace unisph::sph {

// 2: time.cells_per_cutoff; 3: obstacles; 4: initial.settling_*; 5: time.last_acoustic_step and fluid.free_surface_density;
// 6: the general form (gravity vector, free surface, domain, shapes, bodies) and fluid removed from the domain
// 7: domain.periodic (the axes, u64 count then u32 each, and the key's line); the images of periodic
// axes are not stored (the sets' owned particles only), a restore rebuilds them
// 8: each body's translation and rotation (moving walls: law, vectors, numbers, file, line), and
// report.loads (u32) and report.moment_point (f64s) after report.pressure, and the [[gauge]]
// list after the probes (u64 count; name, position, bottom, top, line)
// 10: fluid.wall_continuity (a string after fluid.density_diffusion)
// 11: fluid.wall_pressure (a string after fluid.wall_continuity)
// (older versions are refused with one line).
inline constexpr std::uint32_t solver_checkpoint_version = 11;

void write_case(io::CheckpointWriter& out, const CaseDescription& c);
CaseDescription read_case(io::CheckpointReader& in);

// The first field that determines the state (geometry, fluid, physics, sorting, search,
// probes) in which a and b differ, as "geometry.dx (0.0125 here, 0.025 in the checkpoint)";
// empty when none does. End time and output/checkpoint intervals may differ.
std::string physics_difference(const CaseDescription& here, const CaseDescription& checkpoint);

// What a checkpoint holds, read before a solver is made for it.
struct CheckpointSummary {
  int dimension = 0;
  std::string precision;  // "float" or "double"
  CaseDescription description;
  double time = 0;
  std::uint64_t advection_steps = 0;
  std::uint64_t acoustic_steps = 0;
};
CheckpointSummary read_checkpoint_summary(const std::filesystem::path& path);

}  // namespace unisph::sph
