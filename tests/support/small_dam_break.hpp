#pragma once
// The small dam break the solver tests share: Lobovsky's proportions in units of H, g and rho0
// (a column 2 x 1 in a tank 5.366 long; 3D: 0.5 wide), 2D at dx 0.05 (800 fluid particles),
// 3D at dx 0.1, c0 = 20, stored neighbour lists (the same pairs on every policy), a probe on
// the far wall at 0.2 H. Tests change what they need after the call.
#include "unisph/solver/case_description.hpp"

namespace unisph::testing {

inline sph::CaseDescription small_dam_break(int dimension = 2) {
  sph::CaseDescription c;
  c.name = "small_dam_break";
  c.dimension = dimension;
  c.dx = dimension == 2 ? 0.05 : 0.1;
  c.tank = {5.366, dimension == 2 ? 5.366 : 2.0};
  c.column = {2.0, 1.0};
  if (dimension == 3) {
    c.tank.push_back(0.5);
    c.column.push_back(0.5);
  }
  c.density = 1.0;
  c.sound_speed = 20;
  c.reference_velocity = 2;
  c.gravity = 1;
  c.end_time = 10;
  c.output_interval = 10;
  c.probes = {{"wall", {5.366, 0.2}}};
  if (dimension == 3) c.probes[0].position.push_back(0.25);
  // Stored lists on every policy: the pairs are then fixed at each rebuild everywhere. (The GPU's
  // default direct search re-tests every candidate with the moved positions at each pass, so it
  // sums over slightly different pairs than the CPU's stored lists.)
  c.neighbor_search = "stored";
  return c;
}

}  // namespace unisph::testing
