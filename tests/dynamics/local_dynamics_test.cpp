// The kernel-shell / kernel pattern: kernels built on first use per memory space, reused,
// rebuilt when a viewed variable is reallocated; update, interaction and reduce bases.
#include <cstdint>
#include <vector>

#include "support/policy_test.hpp"
#include "unisph/dynamics/local_dynamics.hpp"
#include "unisph/memory/singular_variable.hpp"

namespace {
using namespace unisph;

// a = b + scale * c
class Triad : public UpdateDynamics<Triad> {
 public:
  Triad(DiscreteVariable<double>& a, DiscreteVariable<double>& b, DiscreteVariable<double>& c, double scale)
      : a_(a), b_(b), c_(c), scale_(scale) {}

  struct Kernel {
    View<double> a;
    View<const double> b, c;
    double scale;
    UNISPH_HOST_DEVICE void update(Index i, Real) const { a[i] = b[i] + scale * c[i]; }
  };
  Kernel make_kernel(KernelContext& context) {
    return {context.write(a_), context.read(b_), context.read(c_), scale_};
  }
  Index size() const { return a_.size(); }

 private:
  DiscreteVariable<double>& a_;
  DiscreteVariable<double>& b_;
  DiscreteVariable<double>& c_;
  double scale_;
};

// out_i = in_{i-1} + in_{i+1} (neighbours by index; reads others, writes only i), plus dt.
class NeighbourSum : public InteractionDynamics<NeighbourSum> {
 public:
  NeighbourSum(DiscreteVariable<double>& in, DiscreteVariable<double>& out) : in_(in), out_(out) {}
  struct Kernel {
    View<const double> in;
    View<double> out;
    UNISPH_HOST_DEVICE void interaction(Index i, Real dt) const {
      double s = dt;
      if (i > 0) s += in[i - 1];
      if (i + 1 < in.size()) s += in[i + 1];
      out[i] = s;
    }
  };
  Kernel make_kernel(KernelContext& context) { return {context.read(in_), context.write(out_)}; }
  Index size() const { return in_.size(); }

 private:
  DiscreteVariable<double>& in_;
  DiscreteVariable<double>& out_;
};

// The largest |v| times a factor held in a SingularVariable; finish() turns it into a speed.
class MaxMagnitude : public ReduceDynamics<MaxMagnitude, Max<double>> {
 public:
  MaxMagnitude(DiscreteVariable<double>& v, SingularVariable<double>& factor) : v_(v), factor_(factor) {}
  struct Kernel {
    View<const double> v;
    View<const double> factor;
    UNISPH_HOST_DEVICE double reduce(Index i, Real) const { return (v[i] < 0 ? -v[i] : v[i]) * factor[0]; }
  };
  Kernel make_kernel(KernelContext& context) { return {context.read(v_), context.read(factor_)}; }
  Index size() const { return v_.size(); }
  double finish(double largest) const { return largest + 0.5; }

 private:
  DiscreteVariable<double>& v_;
  SingularVariable<double>& factor_;
};

static_assert(std::is_trivially_copyable_v<Triad::Kernel>);

UNISPH_POLICY_TEST_SUITE(LocalDynamics);

TYPED_TEST(LocalDynamics, UpdateKernelIsBuiltOnceAndRebuiltOnReallocation) {
  const auto policy = this->policy;
  const MemorySpace space = decltype(policy)::space;
  const Index n = 1000;
  DiscreteVariable<double> a("a", n), b("b", n), c("c", n);
  {
    View<double> hb = b.write(MemorySpace::host), hc = c.write(MemorySpace::host);
    for (Index i = 0; i < n; ++i) hb[i] = double(i), hc[i] = double(2 * i);
  }
  Triad triad(a, b, c, 0.5);
  triad.exec(policy);
  EXPECT_EQ(triad.kernel_builds(space), 1u);
  EXPECT_EQ(a.to_vector()[10], 10.0 + 0.5 * 20.0);

  // Host changes b: the next launch sees them without a rebuild.
  b.write(MemorySpace::host)[10] = 100.0;
  triad.exec(policy);
  EXPECT_EQ(triad.kernel_builds(space), 1u);
  EXPECT_EQ(a.to_vector()[10], 100.0 + 0.5 * 20.0);

  // Resizing every variable reallocates them: the kernel is rebuilt with the new views.
  for (auto* v : {&a, &b, &c}) v->resize(2 * n);
  c.write(MemorySpace::host)[2 * n - 1] = 4.0;
  triad.exec(policy);
  EXPECT_EQ(triad.kernel_builds(space), 2u);
  EXPECT_EQ(a.to_vector()[2 * n - 1], 2.0);
}

TYPED_TEST(LocalDynamics, InteractionReadsNeighbours) {
  const Index n = 5;
  DiscreteVariable<double> in("in", {1, 2, 3, 4, 5}), out("out", n);
  NeighbourSum sum(in, out);
  sum.exec(this->policy, 0.25);
  EXPECT_EQ(out.to_vector(), (std::vector<double>{2.25, 4.25, 6.25, 8.25, 4.25}));
}

TYPED_TEST(LocalDynamics, ReduceWithSingularParameter) {
  DiscreteVariable<double> v("v", {1.0, -7.0, 3.0});
  SingularVariable<double> factor("factor", 2.0);
  MaxMagnitude largest(v, factor);
  EXPECT_EQ(largest.exec(this->policy), 14.5);
  factor.set(3.0);  // a parameter in a SingularVariable reaches the kernel without a rebuild
  EXPECT_EQ(largest.exec(this->policy), 21.5);
  EXPECT_EQ(largest.kernel_builds(decltype(this->policy)::space), 1u);
}

}  // namespace
