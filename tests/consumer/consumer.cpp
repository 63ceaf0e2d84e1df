// Uses the installed unisph: a kernel on every available policy, results checked.
#include <cstdio>

#include <unisph/unisph.hpp>

namespace {
struct Square {
  unisph::View<double> v;
  UNISPH_HOST_DEVICE void operator()(unisph::Index i) const { v[i] = double(i) * double(i); }
};
struct ValueOf {
  unisph::View<const double> v;
  UNISPH_HOST_DEVICE double operator()(unisph::Index i) const { return v[i]; }
};
}  // namespace

int main() {
  const unisph::Index n = 1000;
  const double expected = double(n - 1) * n * (2 * n - 1) / 6;  // sum of i^2
  int failures = 0;
  for (unisph::PolicyKind kind : unisph::execution_info().available) {
    const double sum = unisph::visit_policy(kind, [&](auto policy) {
      unisph::DiscreteVariable<double> v("v", n);
      unisph::particle_for(policy, n, Square{v.write(policy)});
      return unisph::particle_reduce(policy, n, unisph::Sum<double>{}, ValueOf{v.read(policy)});
    });
    std::printf("consumer: %-6s sum of i^2 for i < %zu = %.0f (%s)\n", std::string(unisph::to_string(kind)).c_str(),
                n, sum, sum == expected ? "right" : "WRONG");
    failures += sum != expected;
  }
  return failures == 0 ? 0 : 1;
}
