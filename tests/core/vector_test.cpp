// Small vectors and matrices in float and double, computed inside kernels on every policy
// and compared with values worked out by hand.
#include "support/policy_test.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/exec/algorithms.hpp"

namespace {
using namespace unisph;

template <class T>
struct VectorResults {
  Vec<T, 3> cross3;
  T dot3, norm3, cross2, det3, det2, trace3;
  Vec<T, 3> product3;
  Mat<T, 3> inverse_times_m;
  Mat<T, 2> inverse2_times_m;
};

template <class T>
struct ComputeVectorResults {
  View<VectorResults<T>> out;
  UNISPH_HOST_DEVICE void operator()(Index) const {
    const Vec<T, 3> a{{1, 2, 3}}, b{{4, -5, 6}};
    const Mat<T, 3> m{{{{2, 0, 1}}, {{1, 3, 0}}, {{0, 1, 4}}}};
    const Mat<T, 2> m2{{{{4, 7}}, {{2, 6}}}};
    VectorResults<T> r;
    r.cross3 = cross(a, b);
    r.dot3 = dot(a, b);
    r.norm3 = norm(Vec<T, 3>{{2, 3, 6}});
    r.cross2 = cross(Vec<T, 2>{{1, 2}}, Vec<T, 2>{{3, 4}});
    r.det3 = determinant(m);
    r.det2 = determinant(m2);
    r.trace3 = trace(m);
    r.product3 = m * a + T(2) * b - a / T(2);
    r.inverse_times_m = inverse(m) * m;
    r.inverse2_times_m = inverse(m2) * m2;
    out[0] = r;
  }
};

template <class T, class P>
void check_vectors(P policy) {
  DiscreteVariable<VectorResults<T>> out("results", 1);
  particle_for(policy, 1, ComputeVectorResults<T>{out.write(policy)});
  const VectorResults<T> r = out.to_vector()[0];
  EXPECT_EQ(r.cross3, (Vec<T, 3>{{27, 6, -13}}));
  EXPECT_EQ(r.dot3, T(12));
  EXPECT_EQ(r.norm3, T(7));
  EXPECT_EQ(r.cross2, T(-2));
  EXPECT_EQ(r.det3, T(25));
  EXPECT_EQ(r.det2, T(10));
  EXPECT_EQ(r.trace3, T(9));
  // m*a = (5, 7, 14); + 2b = (13, -3, 26); - a/2 = (12.5, -4, 24.5)
  EXPECT_EQ(r.product3, (Vec<T, 3>{{T(12.5), T(-4), T(24.5)}}));
  const T tolerance = std::is_same_v<T, float> ? T(1e-6) : T(1e-14);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(r.inverse_times_m(i, j), i == j ? T(1) : T(0), tolerance);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) EXPECT_NEAR(r.inverse2_times_m(i, j), i == j ? T(1) : T(0), tolerance);
}

UNISPH_POLICY_TEST_SUITE(Vector);

TYPED_TEST(Vector, FloatInKernels) { check_vectors<float>(this->policy); }
TYPED_TEST(Vector, DoubleInKernels) { check_vectors<double>(this->policy); }

TEST(HostVector, AggregatesAndConstants) {
  constexpr Vec<double, 2> z{};
  static_assert(z[0] == 0.0 && z[1] == 0.0);
  static_assert(Vec<int, 3>::unit(1) == Vec<int, 3>{{0, 1, 0}});
  static_assert(transpose(outer(Vec<int, 2>{{1, 2}}, Vec<int, 2>{{3, 4}}))(0, 1) == 6);
  const Vec<float, 3> x{{1, 2, 3}};
  EXPECT_EQ((Mat<float, 3>::identity() * x), x);
  EXPECT_TRUE((std::is_same_v<Real, std::conditional_t<UNISPH_SINGLE_PRECISION, float, double>>));
}

}  // namespace
