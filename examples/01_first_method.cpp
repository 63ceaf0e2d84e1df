// Example 1: a method in the kernel-shell / kernel pattern, run on a policy chosen at run time.
//
//   example_01_first_method [seq|par|device]
//
// Particles fall under gravity for one explicit Euler step; then the largest speed is reduced.
#include <cmath>
#include <cstdio>
#include <string>

#include <unisph/unisph.hpp>

using namespace unisph;

// [method]
// The kernel shell: holds the variables and parameters, and builds the kernel for a policy.
class GravityStep : public UpdateDynamics<GravityStep> {
 public:
  GravityStep(DiscreteVariable<Vec3d>& position, DiscreteVariable<Vec3d>& velocity, Vec3d gravity)
      : position_(position), velocity_(velocity), gravity_(gravity) {}

  // The kernel: trivially copyable, holds views into the policy's memory, runs anywhere.
  struct Kernel {
    View<Vec3d> position, velocity;
    Vec3d gravity;
    UNISPH_HOST_DEVICE void update(Index i, Real dt) const {
      velocity[i] += gravity * dt;
      position[i] += velocity[i] * dt;
    }
  };
  // Called on first use for a memory space, and again only if a variable was reallocated.
  Kernel make_kernel(KernelContext& context) {
    return {context.read_write(position_), context.read_write(velocity_), gravity_};
  }
  Index size() const { return position_.size(); }

 private:
  DiscreteVariable<Vec3d>& position_;
  DiscreteVariable<Vec3d>& velocity_;
  Vec3d gravity_;
};

// A reduction method: the largest speed.
class MaxSpeed : public ReduceDynamics<MaxSpeed, Max<Real>> {
 public:
  explicit MaxSpeed(DiscreteVariable<Vec3d>& velocity) : velocity_(velocity) {}
  struct Kernel {
    View<const Vec3d> velocity;
    UNISPH_HOST_DEVICE Real reduce(Index i, Real) const { return norm(velocity[i]); }
  };
  Kernel make_kernel(KernelContext& context) { return {context.read(velocity_)}; }
  Index size() const { return velocity_.size(); }

 private:
  DiscreteVariable<Vec3d>& velocity_;
};
// [method]

int main(int argc, char** argv) {
  try {
    const PolicyKind kind = parse_policy(argc > 1 ? argv[1] : "seq");
    // [run]
    const Index n = 100'000;
    DiscreteVariable<Vec3d> position("Position", n), velocity("Velocity", n);
    {
      View<Vec3d> x = position.write(MemorySpace::host);  // set initial positions on the host
      for (Index i = 0; i < n; ++i) x[i] = {{Real(i % 100), Real(i / 100 % 100), Real(i / 10000)}};
    }
    GravityStep step(position, velocity, {{0, -9.81, 0}});
    MaxSpeed max_speed(velocity);
    const Real speed = visit_policy(kind, [&](auto policy) {
      for (int s = 0; s < 10; ++s) step.exec(policy, Real(0.01));  // positions copied to the device once
      return max_speed.exec(policy);                                // waits for the result
    });
    const Vec3d x0 = position.to_vector()[0];  // copies back from the device if it ran there
    // [run]
    std::printf("policy %s: max speed %.6f m/s (expected %.6f), particle 0 at y = %.6f m\n", argv[argc > 1 ? 1 : 0],
                double(speed), 10 * 0.01 * 9.81, double(x0[1]));
    const bool ok = std::abs(double(speed) - 10 * 0.01 * 9.81) < 1e-4 && std::abs(double(x0[1]) + 0.0539550) < 1e-5;
    return ok ? 0 : 1;
  } catch (const Error& e) {
    std::fprintf(stderr, "example_01_first_method: %s\n", e.what());
    return 1;
  }
}
