// Linear sloshing theory in kernels on every policy (double whatever unisph::Real is): natural
// frequencies of a rectangular tank, and the steady free surface under sway against its limits
// (quasi-static tilt, shallow water's closed form), its symmetry and its truncation bound.
// Reference values: Python's mpmath at 30 digits (the modal sum to infinity with nsum).
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/exec/algorithms.hpp"
#include "unisph/motion/linear_waves.hpp"
#include "unisph/motion/sloshing.hpp"

namespace {
using namespace unisph;

constexpr double eps = std::numeric_limits<double>::epsilon();
constexpr double pi = std::numbers::pi;
constexpr double g = 9.81;

// One tank and sway per item: L, h, A, ω, x, modes -> ω_1, ω_3, E(x), E(L/2).
struct Tank {
  double length, depth, amplitude, omega, x;
  int modes;
};
struct Response {
  double omega1, omega3, at_x, at_wall;
};

struct SloshingKernel {
  View<const Tank> tanks;
  View<Response> out;
  UNISPH_HOST_DEVICE void operator()(Index i) const {
    const Tank t = tanks[i];
    out[i] = {sloshing_natural_frequency(1, t.length, t.depth, g), sloshing_natural_frequency(3, t.length, t.depth, g),
              sway_elevation_amplitude(t.x, t.length, t.depth, t.amplitude, t.omega, g, t.modes),
              sway_wall_elevation_amplitude(t.length, t.depth, t.amplitude, t.omega, g, t.modes)};
  }
};

template <class P>
std::vector<Response> respond(P policy, const std::vector<Tank>& tanks) {
  DiscreteVariable<Tank> in("Tanks");
  in.assign(tanks);
  DiscreteVariable<Response> out("Responses", tanks.size());
  particle_for(policy, tanks.size(), SloshingKernel{in.read(policy), out.write(policy)});
  return out.to_vector();
}

UNISPH_POLICY_TEST_SUITE(SloshingTest);

TYPED_TEST(SloshingTest, NaturalFrequencies) {
  // L = 1 m, h = 0.5 m (mpmath: ω_1 = 5.3165533743167515, ω_3 = 9.6146841090650447); a deep
  // tank (tanh = 1 in double): ω_n² = g n π / L; a shallow one: ω_n → n π √(g h) / L.
  const std::vector<Response> r = respond(this->policy, {{1.0, 0.5, 0, 1, 0, 1}, {2.0, 40.0, 0, 1, 0, 1}, {1.0, 1e-6, 0, 1, 0, 1}});
  EXPECT_NEAR(r[0].omega1, 5.316553374316751492, 2 * eps * 5.3);
  EXPECT_NEAR(r[0].omega3, 9.614684109065044654, 2 * eps * 9.6);
  EXPECT_NEAR(r[1].omega1, std::sqrt(g * pi / 2.0), 2 * eps * 2.8);
  EXPECT_NEAR(r[1].omega3, std::sqrt(g * 3 * pi / 2.0), 2 * eps * 4.9);
  EXPECT_NEAR(r[2].omega1, pi * std::sqrt(g * 1e-6), 1e-11 * r[2].omega1);
  EXPECT_NEAR(r[2].omega3, 3 * pi * std::sqrt(g * 1e-6), 1e-10 * r[2].omega3);
  // Each is the dispersion relation's frequency of k_n = n π / L, so wave_number inverts it.
  EXPECT_NEAR(wave_number(r[0].omega1, 0.5, g), pi, 4 * eps * pi);
  EXPECT_NEAR(sloshing_natural_period(1, 1.0, 0.5, g), 2 * pi / r[0].omega1, 2 * eps);
}

TYPED_TEST(SloshingTest, SwayResponseAgainstTheInfiniteModalSum) {
  // L = 1, h = 0.5, A = 1 cm at 0.8 and 1.2 ω_1 (mpmath, every odd mode): 1000 modes leave out
  // the tail the header gives, (A ω²/g) ω² L²/(4 π³ g modes²).
  const double omega1 = 5.316553374316751492;
  const double reference[] = {0.02278017354507731660, -0.03240050004556867310};
  const std::vector<Tank> tanks = {{1.0, 0.5, 0.01, 0.8 * omega1, 0.5, 1000}, {1.0, 0.5, 0.01, 1.2 * omega1, 0.5, 1000}};
  const std::vector<Response> r = respond(this->policy, tanks);
  for (int i = 0; i < 2; ++i) {
    const double w = tanks[i].omega;
    const double tail = 0.01 * w * w / g * w * w / (4 * std::pow(pi, 3) * g * 1000.0 * 1000.0);
    EXPECT_NEAR(r[i].at_wall + tail, reference[i], 0.01 * tail + 64 * eps * 0.03) << i;
    EXPECT_NEAR(r[i].at_x, r[i].at_wall, 64 * eps * 0.03) << i;  // E(L/2), summed with the cosines
  }
  EXPECT_GT(r[0].at_wall, 0.0);  // below the first resonance: up on the wall the tank moves towards
  EXPECT_LT(r[1].at_wall, 0.0);  // above: out of phase
}

TYPED_TEST(SloshingTest, SwayResponseLimitsAndSymmetry) {
  const double L = 1.0, h = 0.5, A = 0.01;
  const double omega1 = sloshing_natural_frequency(1, L, h, g);
  std::vector<Tank> tanks = {
      {L, h, A, 1e-3 * omega1, 0.5, 1000},  // quasi-static: the tilt -Ẍ x / g, E(L/2) = A ω² L / (2 g)
      {L, 1e-3, A, 0.6 * sloshing_natural_frequency(1, L, 1e-3, g), 0.5, 1000},  // shallow water
      {L, h, A, 0.7 * omega1, 0.3, 1000},   // E(x) is odd in x
      {L, h, A, 0.7 * omega1, -0.3, 1000},
      {L, h, A, 0.7 * omega1, 0.0, 1000},
      {L, h, A, 0.999 * omega1, 0.5, 1000},  // near resonance the first mode is all
  };
  const std::vector<Response> r = respond(this->policy, tanks);
  const double w0 = tanks[0].omega;
  EXPECT_NEAR(r[0].at_wall / (A * w0 * w0 / g), L / 2, 1e-5 * L);
  // Shallow water, η_tt = g h η_xx with g η_x = -Ẍ on the walls: E(L/2) = (A ω²/g) tan(κ L/2) / κ,
  // κ = ω / √(g h) (Mittag-Leffler: the same sum when ω_n = k_n √(g h)); the modes' tanh(k_n h)
  // departs from k_n h by (k_n h)²/3.
  const double w1 = tanks[1].omega, kappa = w1 / std::sqrt(g * 1e-3);
  const double shallow = A * w1 * w1 / g * std::tan(kappa * L / 2) / kappa;
  EXPECT_NEAR(r[1].at_wall, shallow, 1e-4 * std::abs(shallow));
  EXPECT_NEAR(r[2].at_x, -r[3].at_x, 64 * eps * std::abs(r[2].at_x));
  EXPECT_NEAR(r[4].at_x, 0.0, 64 * eps * std::abs(r[2].at_x));
  const double w5 = tanks[5].omega, k1 = pi / L;
  const double first_mode = A * w5 * w5 / g * 4 / (L * k1 * k1) * omega1 * omega1 / (omega1 * omega1 - w5 * w5);
  EXPECT_NEAR(r[5].at_wall, first_mode, 0.002 * first_mode);
  EXPECT_GT(r[5].at_wall / (A * w5 * w5 / g * L / 2), 300.0);
}

TEST(HostSloshing, TruncationWithinTheStatedBound) {
  const double L = 0.8, h = 0.3, A = 0.02;
  const double omega = 1.2 * sloshing_natural_frequency(1, L, h, g);
  const double full = sway_wall_elevation_amplitude(L, h, A, omega, g, 200000);
  for (int modes : {30, 100, 1000}) {
    const double tail = A * omega * omega / g * omega * omega * L * L / (4 * std::pow(pi, 3) * g * modes * modes);
    const double left_out = full - sway_wall_elevation_amplitude(L, h, A, omega, g, modes);
    EXPECT_GT(left_out, 0.0) << modes;  // every term beyond is positive above the resonance's mode
    EXPECT_NEAR(left_out, tail, 0.1 * tail) << modes;
  }
  // η(L/2, t) = E(L/2) sin ωt, with the default 1000 modes.
  EXPECT_NEAR(sway_elevation(L / 2, 0.3, L, h, A, omega, g),
              sway_wall_elevation_amplitude(L, h, A, omega, g) * std::sin(omega * 0.3), 64 * eps * std::abs(full));
}

}  // namespace
