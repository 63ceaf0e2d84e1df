// Hydrostatic loads on walls (issue 21, "Hydrostatic loads"), through WallLoad (sph/wall_load.hpp)
// built beside the solver from its public API: water at rest of depth d, settled, in general-form
// tanks whose walls are separate wall bodies (left, right, floor, ...), on every policy:
//  * 2D box tank: the horizontal force on a vertical side wall 1/2 rho g d^2 per unit width
//    within 2 %, the floor's force the water's weight within 1 %;
//  * 2D tank with a 45 degree sloping side (a half-space cut, a body of its own): the normal force
//    on it rho g d^2 / (2 sin 45) within 2 %;
//  * 3D box tank: the same vertical-wall and floor checks (label validation: a longer run).
// Each prints its figures beside its bounds. Units: d = 1, g = 1, rho0 = 1.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/neighbor/cell_linked_list.hpp"
#include "unisph/neighbor/contact_relation.hpp"
#include "unisph/solver/case_file.hpp"
#include "unisph/solver/weakly_compressible_solver.hpp"
#include "unisph/sph/wall_load.hpp"

using namespace unisph;
using namespace unisph::sph;

namespace {

template <class P>
PolicyKind kind_of() {
  if constexpr (P::space == MemorySpace::device) return PolicyKind::device;
  else if constexpr (std::is_same_v<P, SequencedPolicy>) return PolicyKind::seq;
  else return PolicyKind::par;
}

// The loads on a solver's wall bodies, from its public API: its fluid and wall bodies' registered
// variables (the prior acceleration included), its wall bodies' counts, and a cell list and a
// contact relation (fluid -> wall) of our own, built as the solver builds its own.
template <class T, int D>
class SolverWallLoads {
 public:
  SolverWallLoads(WeaklyCompressibleSolver<T, D>& solver, Vec<T, D> moment_point)
      : solver_(solver),
        fluid_(solver.fluid_body()),
        wall_(solver.wall_body()),
        kernel_(WendlandC2Kernel<T, D>::from_spacing(T(solver.description().dx))),
        wall_cells_(wall_.position, domain_of(solver.description()), kernel_.cutoff(), OutsideParticles::clamp),
        contact_(fluid_.position, wall_cells_, SearchMethod::direct),
        load_(fluid_, wall_, solver.wall_body().particles().ids(), solver.wall_body().particles().first_id(),
              counts_of(solver), contact_, kernel_,
              AcousticRiemannSolver<T>::make(T(solver.description().density), T(solver.description().sound_speed)),
              volume_of(solver.description().dx), moment_point) {}

  std::vector<WallBodyLoad<T, D>> measure() {
    return visit_policy(solver_.policy(), [&](auto p) {
      wall_cells_.build(p);
      contact_.update(p);
      return load_.exec(p);
    });
  }
  // The index of the wall body named `name`.
  std::size_t body(const std::string& name) const {
    const auto& bodies = solver_.wall_bodies();
    for (std::size_t b = 0; b < bodies.size(); ++b)
      if (bodies[b].name == name) return b;
    ADD_FAILURE() << "no wall body '" << name << "'";
    return 0;
  }

 private:
  static Box<T, D> domain_of(const CaseDescription& c) {
    Box<T, D> box{};
    for (int a = 0; a < D; ++a) {
      box.lower[a] = T(c.domain.lower[std::size_t(a)]);
      box.upper[a] = T(c.domain.upper[std::size_t(a)]);
    }
    return box;
  }
  static T volume_of(double dx) {
    double v = 1;
    for (int a = 0; a < D; ++a) v *= dx;
    return T(v);
  }
  static std::vector<Index> counts_of(const WeaklyCompressibleSolver<T, D>& solver) {
    std::vector<Index> counts;
    for (const WallBodyCount& b : solver.wall_bodies()) counts.push_back(b.count);
    return counts;
  }

  WeaklyCompressibleSolver<T, D>& solver_;
  FluidVariables<T, D> fluid_;
  WallVariables<T, D> wall_;
  WendlandC2Kernel<T, D> kernel_;
  CellLinkedList<T, D> wall_cells_;
  ContactRelation<T, D> contact_;
  WallLoad<T, D> load_;
};

std::string numbers(const std::vector<double>& v) {
  std::ostringstream s;
  s.precision(17);
  s << "[";
  for (std::size_t k = 0; k < v.size(); ++k) s << (k ? ", " : "") << v[k];
  s << "]";
  return s.str();
}
std::string box_shape(const std::string& name, const std::vector<double>& lower, const std::vector<double>& upper) {
  return "[[shape]]\nname = \"" + name + "\"\ntype = \"box\"\nlower = " + numbers(lower) + "\nupper = " + numbers(upper) +
         "\n";
}
std::string wall_body(const std::string& name) {
  return "[[body]]\nname = \"" + name + "\"\nkind = \"wall\"\nshape = \"" + name + "\"\n";
}
// What every case here shares: the fluid of hydrostatic_2d.toml, water at rest of depth 1
// started hydrostatic and settled.
std::string common(double settling) {
  std::ostringstream s;
  s << "[[body]]\nname = \"water\"\nkind = \"fluid\"\nshape = \"water\"\n"
    << "[fluid]\ndensity = 1.0\nreference_velocity = 2.0\nsound_speed = 20.0\ncontinuity_dissipation = true\n"
    << "[initial]\nstate = \"hydrostatic\"\nfree_surface = 1.0\nsettling_time = " << settling
    << "\nsettling_damping = 1.0\n[time]\nend = 10.0\n";
  return s.str();
}

// A 2D box tank [0, width] x [0, 1.5] holding water of depth 1, its walls three bodies: the
// floor under the whole width (corners included), the left and right walls above it. Each
// wall's box reaches 8 dx beyond the inside, 4 dx beyond the domain (hydrostatic_general_2d.toml).
std::string box_tank_2d(double dx, double width, double settling) {
  const double e = 8 * dx, top = 1.5;
  std::ostringstream s;
  s << "[case]\nname = \"hydrostatic_loads_box_2d\"\ndimension = 2\n[geometry]\ndx = " << dx << "\n"
    << "[domain]\nlower = " << numbers({-4 * dx, -4 * dx}) << "\nupper = " << numbers({width + 4 * dx, top}) << "\n"
    << "leaving = \"stop\"\n[physics]\ngravity = [0.0, -1.0]\n"
    << box_shape("floor", {-e, -e}, {width + e, 0}) << box_shape("left", {-e, 0}, {0, top + e})
    << box_shape("right", {width, 0}, {width + e, top + e}) << box_shape("water", {0, 0}, {width, 1.0})
    << wall_body("floor") << wall_body("left") << wall_body("right") << common(settling);
  return s.str();
}

struct Timer {
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); }
};

}  // namespace

UNISPH_POLICY_TEST_SUITE(HydrostaticLoads);

TYPED_TEST(HydrostaticLoads, BoxTank2D) {
  const double dx = 1.0 / 20, width = 2.0;
  const Timer timer;
  WeaklyCompressibleSolver<double, 2> solver(parse_case(box_tank_2d(dx, width, 20.0), "hydrostatic_loads_box_2d.toml"),
                                             kind_of<TypeParam>());
  SolverWallLoads<double, 2> loads(solver, {{0.0, 0.0}});
  const auto f = loads.measure();
  const double weight = solver.observe().mass;  // g = 1
  const double side = 0.5;                      // 1/2 rho g d^2
  const auto &floor = f[loads.body("floor")], &left = f[loads.body("left")], &right = f[loads.body("right")];
  std::printf("%s 2D box tank, d/dx = %g, width %g d, settled %g (%.1f s): left %.6f (%+.2f %%), right %.6f (%+.2f %%) "
              "against 1/2 rho g d^2 = %g (2 %%); floor %.6f (%+.2f %%) against the weight %.6f (1 %%); "
              "vertical on left/right %.5f / %.5f, horizontal on the floor %.2e\n",
              std::string(TypeParam::test_label).c_str(), 1 / dx, width, solver.settling().time, timer.seconds(),
              -left.force[0], 100 * (-left.force[0] / side - 1), right.force[0], 100 * (right.force[0] / side - 1), side,
              -floor.force[1], 100 * (-floor.force[1] / weight - 1), weight, -left.force[1], -right.force[1],
              floor.force[0]);
  EXPECT_NEAR(-left.force[0] / side, 1.0, 0.02);
  EXPECT_NEAR(right.force[0] / side, 1.0, 0.02);
  EXPECT_NEAR(-floor.force[1] / weight, 1.0, 0.01);
}
