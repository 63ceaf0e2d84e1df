#pragma once
// Shapes on the host: a tree of shared, immutable nodes (primitives, geometry files through their
// level set, booleans, shell, complement, rigid transforms) that compile() turns into a postfix
// program kernels evaluate (compiled_shape.hpp, shape_view.hpp).
//
//   using namespace unisph::shape;
//   Shape<2> tank = difference(box<2>({{-0.1, -0.1}}, {{2.1, 1.1}}), box<2>({{0, 0}}, {{2, 1}}));
//   Shape<2> wedge = intersection_of(box<2>({{1, 0}}, {{1.5, 0.3}}), half_space<2>({{1, 0}}, {{-1, 1}}));
//   Shape<3> hull = rotate(triangle_mesh(cache, "hull.stl", dx), pi / 2, {{0, 0, 1}}, {{0, 0, 0}});
//
// Convention: the signed distance is negative inside the solid (filled) region. Every builder
// checks its arguments and throws ShapeError (one line, beginning "shape: ") for an empty
// operand, a non-positive radius, thickness or scale, a zero-length axis or normal, a box with
// lower >= upper, a boolean of an empty list.

#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "unisph/core/error.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/exec/policy.hpp"
#include "unisph/shape/mesh_level_set.hpp"
#include "unisph/shape/shape_node.hpp"

namespace unisph::shape {

class ShapeError : public Error {
 public:
  using Error::Error;
};

namespace detail {
inline std::string text(Real v) {
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}
template <int D>
std::string text(const Vec<Real, D>& v) {
  std::string s = "(";
  for (int k = 0; k < D; ++k) s += (k ? ", " : "") + text(v[k]);
  return s + ")";
}

// x_world = scale * rotation * x_local + translation.
template <int D>
struct Similarity {
  Mat<Real, D> rotation = Mat<Real, D>::identity();
  Vec<Real, D> translation{};
  Real scale = Real(1);
  bool identity = true;

  // This transform applied after `inner` (inner maps to this one's local frame).
  Similarity after(const Similarity& inner) const {
    if (inner.identity) return *this;
    if (identity) return inner;
    return {rotation * inner.rotation, rotation * inner.translation * scale + translation, scale * inner.scale, false};
  }
  Vec<Real, D> apply(const Vec<Real, D>& x) const { return identity ? x : rotation * x * scale + translation; }
};
}  // namespace detail

template <int D>
struct ShapeTreeNode;

// A shape: a shared handle to an immutable tree node (copies are cheap and share the node).
template <int D>
class Shape {
  static_assert(D == 2 || D == 3, "shapes are 2D or 3D.");

 public:
  Shape() = default;  // empty: refused by every builder and by compile
  explicit Shape(std::shared_ptr<const ShapeTreeNode<D>> node) : node_(std::move(node)) {}
  bool empty() const { return !node_; }
  const ShapeTreeNode<D>& node() const { return *node_; }

 private:
  std::shared_ptr<const ShapeTreeNode<D>> node_;
};

template <int D>
struct ShapeTreeNode {
  enum class Kind { leaf, unite, intersect, subtract, shell, complement, transform };
  Kind kind = Kind::leaf;
  ShapeNode<D> leaf{};                       // a leaf's primitive, in its own frame
  std::shared_ptr<MeshLevelSet<D>> geometry; // a level-set leaf's geometry file
  std::vector<Shape<D>> operands;
  Real half_thickness = Real(0);             // shell
  detail::Similarity<D> transform;           // transform: its operand's frame to this node's
};

namespace detail {
template <int D>
Shape<D> make(ShapeTreeNode<D> node) {
  return Shape<D>(std::make_shared<const ShapeTreeNode<D>>(std::move(node)));
}
template <int D>
Shape<D> leaf(const ShapeNode<D>& primitive) {
  ShapeTreeNode<D> node;
  node.leaf = primitive;
  node.leaf.transformed = false;
  node.leaf.to_local = Mat<Real, D>::identity();
  node.leaf.scale = Real(1);
  return make(std::move(node));
}
template <int D>
void require(const Shape<D>& operand, const char* operation) {
  if (operand.empty()) throw ShapeError(std::string("shape: ") + operation + " of an empty shape");
}
template <int D>
bool finite(const Vec<Real, D>& v) {
  for (int k = 0; k < D; ++k)
    if (!std::isfinite(v[k])) return false;
  return true;
}
template <int D>
Shape<D> binary(typename ShapeTreeNode<D>::Kind kind, const Shape<D>& a, const Shape<D>& b, const char* operation) {
  require(a, operation);
  require(b, operation);
  ShapeTreeNode<D> node;
  node.kind = kind;
  node.operands = {a, b};
  return make(std::move(node));
}
// A balanced tree over [begin, end): the evaluation stack grows with log2 of the count only.
template <int D>
Shape<D> balanced(typename ShapeTreeNode<D>::Kind kind, const std::vector<Shape<D>>& shapes, std::size_t begin,
                  std::size_t end, const char* operation) {
  if (end - begin == 1) return shapes[begin];
  const std::size_t middle = begin + (end - begin) / 2;
  return binary(kind, balanced(kind, shapes, begin, middle, operation), balanced(kind, shapes, middle, end, operation),
                operation);
}
template <int D>
Shape<D> transformed(const Shape<D>& operand, const Similarity<D>& transform, const char* operation) {
  require(operand, operation);
  ShapeTreeNode<D> node;
  node.kind = ShapeTreeNode<D>::Kind::transform;
  node.operands = {operand};
  node.transform = transform;
  return make(std::move(node));
}
}  // namespace detail

// ---- primitives ----

// The axis-aligned box [lower, upper] (rotate it for any other orientation).
template <int D>
Shape<D> box(const Vec<Real, D>& lower, const Vec<Real, D>& upper) {
  for (int k = 0; k < D; ++k)
    if (!(lower[k] < upper[k]) || !std::isfinite(lower[k]) || !std::isfinite(upper[k]))
      throw ShapeError("shape: a box needs finite lower < upper on every axis, got lower " + detail::text(lower) +
                       " and upper " + detail::text(upper));
  ShapeNode<D> n{};
  n.op = ShapeOp::box;
  n.a = (lower + upper) * Real(0.5);
  n.b = (upper - lower) * Real(0.5);
  return detail::leaf(n);
}

// A sphere (a circle in 2D).
template <int D>
Shape<D> sphere(const Vec<Real, D>& centre, Real radius) {
  if (!(radius > Real(0)) || !std::isfinite(radius) || !detail::finite(centre))
    throw ShapeError("shape: a sphere needs a finite centre and a positive radius, got centre " +
                     detail::text(centre) + " and radius " + detail::text(radius));
  ShapeNode<D> n{};
  n.op = ShapeOp::sphere;
  n.a = centre;
  n.radius = radius;
  return detail::leaf(n);
}
inline Shape<2> circle(const Vec<Real, 2>& centre, Real radius) { return sphere<2>(centre, radius); }

// The finite cylinder of the given radius around the segment [start, end], flat ends.
inline Shape<3> cylinder(const Vec<Real, 3>& start, const Vec<Real, 3>& end, Real radius) {
  const Real length = norm(end - start);
  if (!(length > Real(0)) || !std::isfinite(length))
    throw ShapeError("shape: a cylinder needs two different finite axis points, got " + detail::text(start) +
                     " and " + detail::text(end));
  if (!(radius > Real(0)) || !std::isfinite(radius))
    throw ShapeError("shape: a cylinder needs a positive radius, got " + detail::text(radius));
  ShapeNode<3> n{};
  n.op = ShapeOp::cylinder;
  n.a = start;
  n.b = (end - start) / length;
  n.length = length;
  n.radius = radius;
  return detail::leaf(n);
}

// The half-space behind the plane through `point` with outward normal `normal`: the solid is
// where the normal points away from (dot(x - point, normal) < 0).
template <int D>
Shape<D> half_space(const Vec<Real, D>& point, const Vec<Real, D>& normal) {
  const Real length = norm(normal);
  if (!(length > Real(0)) || !std::isfinite(length) || !detail::finite(point))
    throw ShapeError("shape: a half-space needs a finite point and a non-zero normal, got point " +
                     detail::text(point) + " and normal " + detail::text(normal));
  ShapeNode<D> n{};
  n.op = ShapeOp::half_space;
  n.a = point;
  n.b = normal / length;
  return detail::leaf(n);
}

// A geometry file through its level set (mesh_level_set.hpp): an STL file in 3D, a polygon
// file in 2D, at the given data spacing, built once per (file, resolution) in `cache`.
template <int D, ExecutionPolicy P>
Shape<D> geometry_file(P policy, MeshLevelSetCache<D>& cache, const std::string& path, Real resolution) {
  ShapeTreeNode<D> node;
  node.geometry = cache.get(policy, path, resolution);
  node.leaf.op = ShapeOp::level_set;
  node.leaf.to_local = Mat<Real, D>::identity();
  node.leaf.scale = Real(1);
  return detail::make(std::move(node));
}
template <ExecutionPolicy P>
Shape<3> triangle_mesh(P policy, MeshLevelSetCache<3>& cache, const std::string& path, Real resolution) {
  return geometry_file<3>(policy, cache, path, resolution);
}
template <ExecutionPolicy P>
Shape<2> polygon(P policy, MeshLevelSetCache<2>& cache, const std::string& path, Real resolution) {
  return geometry_file<2>(policy, cache, path, resolution);
}
// The same, the level set built on the CPU's threads.
inline Shape<3> triangle_mesh(MeshLevelSetCache<3>& cache, const std::string& path, Real resolution) {
  return triangle_mesh(par, cache, path, resolution);
}
inline Shape<2> polygon(MeshLevelSetCache<2>& cache, const std::string& path, Real resolution) {
  return polygon(par, cache, path, resolution);
}

// ---- booleans (min, max, max(a, -b) of the signed distances) ----

template <int D>
Shape<D> union_of(const Shape<D>& a, const Shape<D>& b) {
  return detail::binary(ShapeTreeNode<D>::Kind::unite, a, b, "a union");
}
template <int D>
Shape<D> union_of(const std::vector<Shape<D>>& shapes) {
  if (shapes.empty()) throw ShapeError("shape: a union of nothing (the list of shapes is empty)");
  for (const Shape<D>& s : shapes) detail::require(s, "a union");
  return detail::balanced(ShapeTreeNode<D>::Kind::unite, shapes, 0, shapes.size(), "a union");
}
template <int D>
Shape<D> intersection_of(const Shape<D>& a, const Shape<D>& b) {
  return detail::binary(ShapeTreeNode<D>::Kind::intersect, a, b, "an intersection");
}
template <int D>
Shape<D> intersection_of(const std::vector<Shape<D>>& shapes) {
  if (shapes.empty()) throw ShapeError("shape: an intersection of nothing (the list of shapes is empty)");
  for (const Shape<D>& s : shapes) detail::require(s, "an intersection");
  return detail::balanced(ShapeTreeNode<D>::Kind::intersect, shapes, 0, shapes.size(), "an intersection");
}
// a without b.
template <int D>
Shape<D> difference(const Shape<D>& a, const Shape<D>& b) {
  return detail::binary(ShapeTreeNode<D>::Kind::subtract, a, b, "a difference");
}

// The band of the given thickness centred on a's surface, |d| - thickness / 2: a thin plate
// wetted on both sides from a half-space or a polygon line, a hollow sphere from a sphere.
template <int D>
Shape<D> shell(const Shape<D>& a, Real thickness) {
  detail::require(a, "a shell");
  if (!(thickness > Real(0)) || !std::isfinite(thickness))
    throw ShapeError("shape: a shell needs a positive thickness, got " + detail::text(thickness));
  ShapeTreeNode<D> node;
  node.kind = ShapeTreeNode<D>::Kind::shell;
  node.operands = {a};
  node.half_thickness = Real(0.5) * thickness;
  return detail::make(std::move(node));
}

// Everything outside a (-d): e.g. the solid around a container's inside.
template <int D>
Shape<D> complement(const Shape<D>& a) {
  detail::require(a, "a complement");
  ShapeTreeNode<D> node;
  node.kind = ShapeTreeNode<D>::Kind::complement;
  node.operands = {a};
  return detail::make(std::move(node));
}

// ---- rigid transforms and uniform scale ----

template <int D>
Shape<D> translate(const Shape<D>& a, const Vec<Real, D>& offset) {
  if (!detail::finite(offset)) throw ShapeError("shape: a translation needs a finite offset, got " + detail::text(offset));
  detail::Similarity<D> t;
  t.translation = offset;
  t.identity = false;
  return detail::transformed(a, t, "a translation");
}

// 2D: by `angle` (radians, counter-clockwise) about `centre`.
inline Shape<2> rotate(const Shape<2>& a, Real angle, const Vec<Real, 2>& centre) {
  if (!std::isfinite(angle) || !detail::finite(centre))
    throw ShapeError("shape: a rotation needs a finite angle and centre, got " + detail::text(angle) + " about " +
                     detail::text(centre));
  detail::Similarity<2> t;
  const Real c = std::cos(angle), s = std::sin(angle);
  t.rotation(0, 0) = c;
  t.rotation(0, 1) = -s;
  t.rotation(1, 0) = s;
  t.rotation(1, 1) = c;
  t.translation = centre - t.rotation * centre;
  t.identity = false;
  return detail::transformed(a, t, "a rotation");
}

// 3D: by `angle` (radians, right-handed) about the axis through `point` along `axis`.
inline Shape<3> rotate(const Shape<3>& a, Real angle, const Vec<Real, 3>& axis, const Vec<Real, 3>& point) {
  const Real length = norm(axis);
  if (!(length > Real(0)) || !std::isfinite(length))
    throw ShapeError("shape: a rotation needs a non-zero axis, got " + detail::text(axis));
  if (!std::isfinite(angle) || !detail::finite(point))
    throw ShapeError("shape: a rotation needs a finite angle and point, got " + detail::text(angle) + " about " +
                     detail::text(point));
  const Vec<Real, 3> u = axis / length;
  const Real c = std::cos(angle), s = std::sin(angle);
  // Rodrigues: R = c I + s [u]x + (1 - c) u u^T.
  Mat<Real, 3> r = Mat<Real, 3>::identity() * c + outer(u, u) * (Real(1) - c);
  r(0, 1) -= s * u[2];
  r(0, 2) += s * u[1];
  r(1, 0) += s * u[2];
  r(1, 2) -= s * u[0];
  r(2, 0) -= s * u[1];
  r(2, 1) += s * u[0];
  detail::Similarity<3> t;
  t.rotation = r;
  t.translation = point - r * point;
  t.identity = false;
  return detail::transformed(a, t, "a rotation");
}

// Uniform scale by `factor` about `centre`: distances scale with it.
template <int D>
Shape<D> scale(const Shape<D>& a, Real factor, const Vec<Real, D>& centre = Vec<Real, D>{}) {
  if (!(factor > Real(0)) || !std::isfinite(factor))
    throw ShapeError("shape: a scale needs a positive factor, got " + detail::text(factor));
  if (!detail::finite(centre)) throw ShapeError("shape: a scale needs a finite centre, got " + detail::text(centre));
  detail::Similarity<D> t;
  t.scale = factor;
  t.translation = centre - centre * factor;
  t.identity = false;
  return detail::transformed(a, t, "a scale");
}

}  // namespace unisph::shape
