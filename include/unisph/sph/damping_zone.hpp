#pragma once
// Damping zone: passive wave absorption at the far end of a flume (issue 22, "Wave absorption";
// docs/motion.md, "Measurements and wave absorption"). In a zone [x0, x1] along a horizontal unit
// direction e, each fluid particle's velocity is relaxed towards zero at every acoustic step:
//
//   xi = (x.e - x0) / (x1 - x0)                          (0 at the zone's start, 1 at its end)
//   sigma(xi) = beta s(xi)^2,   s(xi) = xi                (the damping rate, 1/time)
//   linear:       v <- v max(0, 1 - dt sigma)             (the default)
//   exponential:  v <- v exp(-dt sigma)
//
// so that the velocity decays as exp(-sigma t) (to first order in sigma dt for the linear form:
// after n steps (1 - dt sigma)^n = exp(-sigma t) (1 - sigma^2 dt t / 2 + ...)). Particles outside
// [x0, x1] are not touched: put x1 at the end wall (or beyond it).
//
// The profile. sigma rises from 0 with zero slope at the zone's start, so the wave enters a
// medium whose damping grows gradually: an abrupt jump of the damping reflects part of the wave
// itself (Israeli & Orszag 1981, sponge layers, J. Comput. Phys. 41, 115-135). The quadratic
// ramp beta xi^2 is the damping of DualSPHysics' passive absorption (Altomare et al. 2017,
// Coastal Engineering 127, 37-54: v = v0 (1 - dt beta xi^2), the linear form here); power laws
// of xi with their reflection are studied by Carmigniani & Violeau (2018, Ocean Engineering 163,
// 169-182) and predicted analytically by Peric & Abdel-Maksoud (arXiv:1705.06940, 2017).
// All velocity components are damped.
//
// The strength beta (1/time). For linear waves with the momentum damped as dv/dt = -sigma v the
// dispersion relation becomes w (w + i sigma) = g k tanh kd, so at a fixed frequency and for
// sigma << w the amplitude decays along the zone as exp(-int sigma / (2 c_g) dx) (c_g the group
// velocity). A wave that crosses the zone, meets the end wall and crosses back leaves it with
// the amplitude factor
//
//   a = exp(-int_0^Lz sigma dx / c_g) = exp(-beta Lz / (3 c_g))       (int_0^1 xi^2 = 1/3)
//
// (damping_round_trip_amplitude; damping_strength_for inverts it: beta = 3 c_g ln(1/a) / Lz).
// This estimate leaves out the reflection at the gradient of the damping itself, which grows
// with beta / w, and it assumes sigma << w: over a zone of one wave length (damping_zone_length)
// a = 1 % asks for beta = 13.8 c_g / L = 2.2 w c_g / c (between 1.1 w in deep water and 2.2 w in
// shallow water), so sigma is not small near the zone's end and the figure is a first guess.
// Measure the reflection (two gauges, docs/motion.md) rather than trust it.
//
// Where the solver calls it: after the velocity update of each acoustic step, with that step's
// dt (as the settling's VelocityDamping). The kernel refreshes the neighbour records of the
// particles it damps (the records carry v).
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <type_traits>

#include "unisph/core/error.hpp"
#include "unisph/core/uncontracted_arithmetic.hpp"
#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/motion/linear_waves.hpp"
#include "unisph/sph/fluid_variables.hpp"
#include "unisph/sph/neighbor_records.hpp"

namespace unisph::sph {

enum class DampingForm : std::uint8_t {
  linear,       // v *= max(0, 1 - dt sigma): the same bits on every policy
  exponential,  // v *= exp(-dt sigma): never past zero; the device's exp may differ from the host's by an ulp
};

// The factor a particle's velocity is multiplied by at xi in [0, 1] over a step dt: the zone's
// arithmetic, host and device, every product and difference rounded on its own (no FMA), so that
// the linear form gives the same bits on every policy.
template <class T>
UNISPH_HOST_DEVICE T damping_factor(T xi, T strength, T dt, DampingForm form) {
  const T rate_dt = uncontracted::mul(uncontracted::mul(strength, dt), uncontracted::mul(xi, xi));
  if (form == DampingForm::exponential) return std::exp(-rate_dt);
  const T keep = uncontracted::sub(T(1), rate_dt);
  return keep > T(0) ? keep : T(0);
}

// xi = (x.e - x0) / (x1 - x0) for the unit direction e, x0 = start and 1 / (x1 - x0) =
// inverse_length, rounded the same way on every policy; NaN for a NaN position (not damped).
template <class T, int D>
UNISPH_HOST_DEVICE T damping_zone_coordinate(const Vec<T, D>& x, const Vec<T, D>& direction, T start, T inverse_length) {
  T along = uncontracted::mul(x[0], direction[0]);
  for (int a = 1; a < D; ++a) along = uncontracted::add(along, uncontracted::mul(x[a], direction[a]));
  return uncontracted::mul(uncontracted::sub(along, start), inverse_length);
}

template <class T, int D>
class DampingZone : public UpdateDynamics<DampingZone<T, D>> {
 public:
  // The zone from `start` to `end` (coordinates along `direction`, which need not be a unit
  // vector), damping rate beta xi^2 with beta = `strength` (1/time). Throws unisph::Error (one
  // line) for a zero or non-finite direction, end not beyond start, or a negative strength.
  DampingZone(FluidVariables<T, D>& fluid, Vec<T, D> direction, T start, T end, T strength,
              DampingForm form = DampingForm::linear)
      : fluid_(fluid), start_(start), end_(end), strength_(strength), form_(form) {
    const T length = std::sqrt(squared_norm(direction));
    if (!(length > T(0)) || !(length < std::numeric_limits<T>::infinity()))
      throw Error("damping zone: the direction must be finite and not zero");
    direction_ = direction * (T(1) / length);
    if (!std::isfinite(start) || !std::isfinite(end) || !(end > start))
      throw Error("damping zone: the end (" + std::to_string(end) + ") must be beyond the start (" +
                  std::to_string(start) + "), both finite");
    if (!(strength >= T(0)) || !(strength < std::numeric_limits<T>::infinity()))
      throw Error("damping zone: the strength must be finite and >= 0 (it is " + std::to_string(strength) + ")");
    inverse_length_ = T(1) / (end - start);
  }

  struct Kernel {
    View<const Vec<T, D>> position;
    View<Vec<T, D>> velocity;
    View<const T> pressure, mass, density;
    NeighborRecordWriter<T, D> records;  // rewritten for the damped particles only
    Vec<T, D> direction;
    T start, inverse_length, strength;
    DampingForm form;
    // `dt`: the acoustic step.
    UNISPH_HOST_DEVICE void update(Index i, Real dt) const {
      const Vec<T, D> x = position[i];
      const T xi = damping_zone_coordinate(x, direction, start, inverse_length);
      if (!(xi >= T(0) && xi <= T(1))) return;
      const Vec<T, D> v = velocity[i] * damping_factor(xi, strength, T(dt), form);
      velocity[i] = v;
      records.store(i, x, v, pressure[i], mass[i], density[i]);
    }
  };
  static_assert(std::is_trivially_copyable_v<Kernel>, "Kernels are copied to the device byte for byte.");
  Kernel make_kernel(KernelContext& c) {
    // read_write, not write: the particles outside the zone keep their velocity and records.
    return {c.read(fluid_.position),
            c.read_write(fluid_.velocity),
            c.read(fluid_.pressure),
            c.read(fluid_.mass),
            c.read(fluid_.density),
            NeighborRecordWriter<T, D>{c.read_write(fluid_.neighbor_position_volume),
                                       c.read_write(fluid_.neighbor_velocity_pressure)},
            direction_,
            start_,
            inverse_length_,
            strength_,
            form_};
  }
  Index size() const { return fluid_.size(); }

  // The zone coordinate xi of a point, as the kernel computes it (outside [0, 1]: not damped).
  T coordinate(const Vec<T, D>& x) const { return damping_zone_coordinate(x, direction_, start_, inverse_length_); }
  const Vec<T, D>& direction() const { return direction_; }
  T start() const { return start_; }
  T end() const { return end_; }
  T strength() const { return strength_; }
  DampingForm form() const { return form_; }

 private:
  FluidVariables<T, D>& fluid_;
  Vec<T, D> direction_{};
  T start_, end_, strength_;
  DampingForm form_;
  T inverse_length_ = T(1);
};

// The group velocity of a linear wave of period `period` in water of depth `depth`:
// c_g = (c / 2) (1 + 2kd / sinh 2kd), c = w / k, with 2kd / sinh 2kd written as
// 4kd q / (1 - q^2), q = e^(-2kd), which neither overflows nor cancels (c_g -> c/2 in deep water,
// -> sqrt(g d) in shallow water). NaN for invalid arguments (those of wave_number).
template <class T>
UNISPH_HOST_DEVICE T wave_group_velocity(T period, T depth, T g) {
  const T omega = T(2) * std::numbers::pi_v<T> / period;
  const T k = wave_number(omega, depth, g);
  const T kd = k * depth;
  T ratio;  // 2kd / sinh 2kd
  if (kd == T(0))
    ratio = T(1);
  else if (!(kd < std::numeric_limits<T>::infinity()))
    ratio = T(0);
  else
    ratio = T(4) * kd * std::exp(T(-2) * kd) / -std::expm1(T(-4) * kd);
  return T(0.5) * (omega / k) * (T(1) + ratio);
}

// The recommended length of a damping zone: `wavelengths` (1 by default) wave lengths of the
// linear wave of the period in the depth, L = 2 pi / k with w^2 = g k tanh kd (linear_waves.hpp).
template <class T>
UNISPH_HOST_DEVICE T damping_zone_length(T period, T depth, T g, T wavelengths = T(1)) {
  return wavelengths * wave_length(period, depth, g);
}

// The amplitude factor of a wave that crosses a zone of length `zone_length` with strength
// `strength` (the quadratic profile), meets the end wall and crosses back:
// exp(-strength zone_length / (3 c_g)) (the header comment; weak damping, no gradient reflection).
template <class T>
UNISPH_HOST_DEVICE T damping_round_trip_amplitude(T strength, T zone_length, T period, T depth, T g) {
  return std::exp(-strength * zone_length / (T(3) * wave_group_velocity(period, depth, g)));
}

// The strength that gives the round-trip amplitude factor `amplitude` (in (0, 1)):
// 3 c_g ln(1 / amplitude) / zone_length.
template <class T>
UNISPH_HOST_DEVICE T damping_strength_for(T amplitude, T zone_length, T period, T depth, T g) {
  return T(3) * wave_group_velocity(period, depth, g) * -std::log(amplitude) / zone_length;
}

}  // namespace unisph::sph
