#pragma once
// Small fixed-size vectors and matrices for 2D and 3D, usable in host and device code.
//
// Why not Eigen: Eigen 3.4 (Debian 12) compiles under nvcc 13 but its fixed-size types are
// not trivially copyable (g++ 12 reports std::is_trivially_copyable_v<Eigen::Vector3d> ==
// false), and unisph kernels and variables must be, because they are copied to the device
// byte for byte. See docs/architecture.md ("Small vector types").
//
// Vec and Mat are aggregates: `Vec<double, 3> v{};` is all zeros, `Vec<double, 3> v;` is
// uninitialised, exactly like a built-in array.

#include <cmath>
#include <type_traits>

#include "unisph/core/config.hpp"

namespace unisph {

template <class T, int D>
struct Vec {
  static_assert(D >= 1 && D <= 4, "unisph::Vec is meant for 1 to 4 components (2D and 3D geometry).");
  static_assert(std::is_arithmetic_v<T>, "unisph::Vec holds arithmetic components (float, double, int...).");
  using value_type = T;
  static constexpr int size = D;

  T v[D];

  UNISPH_HOST_DEVICE constexpr T& operator[](int i) { return v[i]; }
  UNISPH_HOST_DEVICE constexpr const T& operator[](int i) const { return v[i]; }

  UNISPH_HOST_DEVICE static constexpr Vec constant(T value) {
    Vec r{};
    for (int i = 0; i < D; ++i) r.v[i] = value;
    return r;
  }
  UNISPH_HOST_DEVICE static constexpr Vec zero() { return Vec{}; }
  UNISPH_HOST_DEVICE static constexpr Vec unit(int axis) {
    Vec r{};
    r.v[axis] = T(1);
    return r;
  }

  UNISPH_HOST_DEVICE constexpr Vec& operator+=(const Vec& o) {
    for (int i = 0; i < D; ++i) v[i] += o.v[i];
    return *this;
  }
  UNISPH_HOST_DEVICE constexpr Vec& operator-=(const Vec& o) {
    for (int i = 0; i < D; ++i) v[i] -= o.v[i];
    return *this;
  }
  UNISPH_HOST_DEVICE constexpr Vec& operator*=(T s) {
    for (int i = 0; i < D; ++i) v[i] *= s;
    return *this;
  }
  UNISPH_HOST_DEVICE constexpr Vec& operator/=(T s) {
    for (int i = 0; i < D; ++i) v[i] /= s;
    return *this;
  }
  friend UNISPH_HOST_DEVICE constexpr Vec operator+(Vec a, const Vec& b) { return a += b; }
  friend UNISPH_HOST_DEVICE constexpr Vec operator-(Vec a, const Vec& b) { return a -= b; }
  friend UNISPH_HOST_DEVICE constexpr Vec operator*(Vec a, T s) { return a *= s; }
  friend UNISPH_HOST_DEVICE constexpr Vec operator*(T s, Vec a) { return a *= s; }
  friend UNISPH_HOST_DEVICE constexpr Vec operator/(Vec a, T s) { return a /= s; }
  friend UNISPH_HOST_DEVICE constexpr Vec operator-(Vec a) {
    for (int i = 0; i < D; ++i) a.v[i] = -a.v[i];
    return a;
  }
  friend UNISPH_HOST_DEVICE constexpr bool operator==(const Vec& a, const Vec& b) {
    for (int i = 0; i < D; ++i)
      if (!(a.v[i] == b.v[i])) return false;
    return true;
  }
  friend UNISPH_HOST_DEVICE constexpr bool operator!=(const Vec& a, const Vec& b) { return !(a == b); }
};

template <class T, int D>
UNISPH_HOST_DEVICE constexpr T dot(const Vec<T, D>& a, const Vec<T, D>& b) {
  T s{};
  for (int i = 0; i < D; ++i) s += a[i] * b[i];
  return s;
}
template <class T, int D>
UNISPH_HOST_DEVICE constexpr T squared_norm(const Vec<T, D>& a) {
  return dot(a, a);
}
template <class T, int D>
UNISPH_HOST_DEVICE T norm(const Vec<T, D>& a) {
  return std::sqrt(squared_norm(a));
}
template <class T>
UNISPH_HOST_DEVICE constexpr Vec<T, 3> cross(const Vec<T, 3>& a, const Vec<T, 3>& b) {
  return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}
// The scalar cross product of 2D vectors (z component of the 3D one).
template <class T>
UNISPH_HOST_DEVICE constexpr T cross(const Vec<T, 2>& a, const Vec<T, 2>& b) {
  return a[0] * b[1] - a[1] * b[0];
}
template <class T, int D>
UNISPH_HOST_DEVICE constexpr Vec<T, D> min(const Vec<T, D>& a, const Vec<T, D>& b) {
  Vec<T, D> r{};
  for (int i = 0; i < D; ++i) r[i] = b[i] < a[i] ? b[i] : a[i];
  return r;
}
template <class T, int D>
UNISPH_HOST_DEVICE constexpr Vec<T, D> max(const Vec<T, D>& a, const Vec<T, D>& b) {
  Vec<T, D> r{};
  for (int i = 0; i < D; ++i) r[i] = a[i] < b[i] ? b[i] : a[i];
  return r;
}

// Row-major D x D matrix.
template <class T, int D>
struct Mat {
  static_assert(D >= 1 && D <= 4, "unisph::Mat is meant for 1x1 to 4x4 matrices (2D and 3D geometry).");
  using value_type = T;
  static constexpr int size = D;

  Vec<T, D> row[D];

  UNISPH_HOST_DEVICE constexpr T& operator()(int i, int j) { return row[i][j]; }
  UNISPH_HOST_DEVICE constexpr const T& operator()(int i, int j) const { return row[i][j]; }

  UNISPH_HOST_DEVICE static constexpr Mat identity() {
    Mat m{};
    for (int i = 0; i < D; ++i) m.row[i][i] = T(1);
    return m;
  }
  UNISPH_HOST_DEVICE constexpr Mat& operator+=(const Mat& o) {
    for (int i = 0; i < D; ++i) row[i] += o.row[i];
    return *this;
  }
  UNISPH_HOST_DEVICE constexpr Mat& operator-=(const Mat& o) {
    for (int i = 0; i < D; ++i) row[i] -= o.row[i];
    return *this;
  }
  UNISPH_HOST_DEVICE constexpr Mat& operator*=(T s) {
    for (int i = 0; i < D; ++i) row[i] *= s;
    return *this;
  }
  friend UNISPH_HOST_DEVICE constexpr Mat operator+(Mat a, const Mat& b) { return a += b; }
  friend UNISPH_HOST_DEVICE constexpr Mat operator-(Mat a, const Mat& b) { return a -= b; }
  friend UNISPH_HOST_DEVICE constexpr Mat operator*(Mat a, T s) { return a *= s; }
  friend UNISPH_HOST_DEVICE constexpr Mat operator*(T s, Mat a) { return a *= s; }
  friend UNISPH_HOST_DEVICE constexpr Vec<T, D> operator*(const Mat& m, const Vec<T, D>& x) {
    Vec<T, D> r{};
    for (int i = 0; i < D; ++i) r[i] = dot(m.row[i], x);
    return r;
  }
  friend UNISPH_HOST_DEVICE constexpr Mat operator*(const Mat& a, const Mat& b) {
    Mat r{};
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j)
        for (int k = 0; k < D; ++k) r.row[i][j] += a.row[i][k] * b.row[k][j];
    return r;
  }
  friend UNISPH_HOST_DEVICE constexpr bool operator==(const Mat& a, const Mat& b) {
    for (int i = 0; i < D; ++i)
      if (a.row[i] != b.row[i]) return false;
    return true;
  }
};

template <class T, int D>
UNISPH_HOST_DEVICE constexpr Mat<T, D> transpose(const Mat<T, D>& m) {
  Mat<T, D> r{};
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) r.row[j][i] = m.row[i][j];
  return r;
}
// a b^T
template <class T, int D>
UNISPH_HOST_DEVICE constexpr Mat<T, D> outer(const Vec<T, D>& a, const Vec<T, D>& b) {
  Mat<T, D> r{};
  for (int i = 0; i < D; ++i) r.row[i] = a[i] * b;
  return r;
}
template <class T>
UNISPH_HOST_DEVICE constexpr T determinant(const Mat<T, 2>& m) {
  return m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0);
}
template <class T>
UNISPH_HOST_DEVICE constexpr T determinant(const Mat<T, 3>& m) {
  return dot(m.row[0], cross(m.row[1], m.row[2]));
}
template <class T, int D>
UNISPH_HOST_DEVICE constexpr T trace(const Mat<T, D>& m) {
  T s{};
  for (int i = 0; i < D; ++i) s += m(i, i);
  return s;
}
// Inverse of a regular matrix (the caller checks the determinant where it may vanish).
template <class T>
UNISPH_HOST_DEVICE constexpr Mat<T, 2> inverse(const Mat<T, 2>& m) {
  const T inv = T(1) / determinant(m);
  return {{{{m(1, 1) * inv, -m(0, 1) * inv}}, {{-m(1, 0) * inv, m(0, 0) * inv}}}};
}
template <class T>
UNISPH_HOST_DEVICE constexpr Mat<T, 3> inverse(const Mat<T, 3>& m) {
  const T inv = T(1) / determinant(m);
  // Rows of the inverse are the cross products of the columns: use the transpose's rows.
  const Mat<T, 3> t = transpose(m);
  Mat<T, 3> r{};
  r.row[0] = cross(t.row[1], t.row[2]) * inv;
  r.row[1] = cross(t.row[2], t.row[0]) * inv;
  r.row[2] = cross(t.row[0], t.row[1]) * inv;
  return r;
}

template <int D>
using Vecd = Vec<Real, D>;
template <int D>
using Matd = Mat<Real, D>;
using Vec2d = Vec<Real, 2>;
using Vec3d = Vec<Real, 3>;
using Mat2d = Mat<Real, 2>;
using Mat3d = Mat<Real, 3>;

static_assert(std::is_trivially_copyable_v<Vec<double, 3>> && std::is_trivially_default_constructible_v<Vec<double, 3>>);
static_assert(std::is_trivially_copyable_v<Mat<float, 3>> && std::is_trivially_default_constructible_v<Mat<float, 3>>);

}  // namespace unisph
