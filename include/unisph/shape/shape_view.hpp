#pragma once
// A compiled shape as kernels see it: the postfix program (shape_node.hpp) and the level-set
// views its mesh and polygon leaves probe, both in one memory space. Trivially copyable, so a
// kernel holds it by value:
//
//   struct MarkInside {
//     shape::ShapeView<3> solid;
//     View<const Vec3d> x;
//     View<int> inside;
//     UNISPH_HOST_DEVICE void operator()(Index i) const { inside[i] = solid.inside(x[i]); }
//   };
//
// Signed distance is negative inside the solid. Primitives give it exactly (to round-off);
// level-set leaves give the level set's interpolated phi (accurate in its band, only the right
// sign beyond it); booleans give min / max / max(a, -b) of their operands, which is the exact
// distance only where one operand's surface is the nearest: elsewhere (inside a union, outside
// an intersection, near the edges a difference cuts) it is a bound of the distance, with the
// right sign everywhere.

#include <cmath>
#include <type_traits>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"
#include "unisph/levelset/multi_resolution_level_set_view.hpp"
#include "unisph/memory/view.hpp"
#include "unisph/shape/shape_node.hpp"

namespace unisph::shape {

// The evaluation stack lives in each thread's registers or local memory, so its size is fixed.
// A tree needs as many entries as the deepest chain of right operands; compile refuses deeper
// trees with a message (union_of / intersection_of of a list build balanced trees, which need
// only log2 of the count).
inline constexpr int max_shape_stack = 16;
static_assert(max_shape_stack >= 2 && max_shape_stack <= 64,
              "the shape stack is a per-thread array of Reals: at least 2 entries for a boolean, and few enough "
              "to stay in registers or local memory on the GPU.");

// A level-set view's bytes, so that a DiscreteVariable (whose elements must be trivially default
// constructible, which a View's default member initialisers are not) can hold a table of them.
// The bytes are written by copying a whole view in (which begins its lifetime there) and read in
// place through view().
template <int D>
struct alignas(MultiResolutionLevelSetView<D>) LevelSetViewStorage {
  unsigned char bytes[sizeof(MultiResolutionLevelSetView<D>)];
  UNISPH_HOST_DEVICE const MultiResolutionLevelSetView<D>& view() const {
    return *reinterpret_cast<const MultiResolutionLevelSetView<D>*>(bytes);
  }
};

template <int D>
struct ShapeView {
  using Vector = Vec<Real, D>;
  View<const ShapeNode<D>> program;
  View<const LevelSetViewStorage<D>> level_sets;

  UNISPH_HOST_DEVICE Real signed_distance(const Vector& x) const {
    Real stack[max_shape_stack];
    stack[0] = Real(0);  // an empty program (never compiled) reads 0
    int top = 0;
    for (Index i = 0; i < program.size(); ++i) {
      const ShapeNode<D>& node = program[i];
      switch (node.op) {
        case ShapeOp::unite:
          --top;
          stack[top - 1] = stack[top] < stack[top - 1] ? stack[top] : stack[top - 1];
          break;
        case ShapeOp::intersect:
          --top;
          stack[top - 1] = stack[top] > stack[top - 1] ? stack[top] : stack[top - 1];
          break;
        case ShapeOp::subtract:
          --top;
          stack[top - 1] = -stack[top] > stack[top - 1] ? -stack[top] : stack[top - 1];
          break;
        case ShapeOp::shell:
          stack[top - 1] = (stack[top - 1] < Real(0) ? -stack[top - 1] : stack[top - 1]) - node.radius;
          break;
        case ShapeOp::complement:
          stack[top - 1] = -stack[top - 1];
          break;
        default:
          stack[top++] = leaf_distance(node, x);
      }
    }
    return stack[0];
  }

  UNISPH_HOST_DEVICE bool inside(const Vector& x) const { return signed_distance(x) < Real(0); }

  // The unit normal out of the solid: the gradient of the signed distance by central differences
  // of the given step (zero where they cancel, e.g. at the centre of a sphere). On the medial
  // surface of a primitive (the diagonal of a box) this averages the two sides' normals.
  UNISPH_HOST_DEVICE Vector normal(const Vector& x, Real step) const {
    Vector gradient{};
    for (int k = 0; k < D; ++k) {
      Vector forward = x, backward = x;
      forward[k] += step;
      backward[k] -= step;
      gradient[k] = signed_distance(forward) - signed_distance(backward);
    }
    const Real length = norm(gradient);
    return length > Real(0) ? gradient / length : gradient;
  }

 private:
  UNISPH_HOST_DEVICE Real leaf_distance(const ShapeNode<D>& node, const Vector& x) const {
    if (!node.transformed) return local_distance(node, x);
    const Vector y = (node.to_local * (x - node.origin)) / node.scale;
    return node.scale * local_distance(node, y);
  }

  UNISPH_HOST_DEVICE Real local_distance(const ShapeNode<D>& node, const Vector& y) const {
    switch (node.op) {
      case ShapeOp::box: {
        Real outside2 = Real(0), largest = Real(0);
        for (int k = 0; k < D; ++k) {
          const Real offset = y[k] - node.a[k];
          const Real q = (offset < Real(0) ? -offset : offset) - node.b[k];
          if (q > Real(0)) outside2 += q * q;
          largest = k == 0 || q > largest ? q : largest;
        }
        return largest > Real(0) ? std::sqrt(outside2) : largest;
      }
      case ShapeOp::sphere: {
        return norm(y - node.a) - node.radius;
      }
      case ShapeOp::cylinder: {
        // A box in (distance from the axis, position along it).
        const Vector from_start = y - node.a;
        const Real along = dot(from_start, node.b);
        const Real radial = norm(from_start - node.b * along) - node.radius;
        const Real half = Real(0.5) * node.length;
        const Real centred = along - half;
        const Real axial = (centred < Real(0) ? -centred : centred) - half;
        const Real r = radial > Real(0) ? radial : Real(0), z = axial > Real(0) ? axial : Real(0);
        const Real largest = radial > axial ? radial : axial;
        return largest > Real(0) ? std::sqrt(r * r + z * z) : largest;
      }
      case ShapeOp::half_space:
        return dot(y - node.a, node.b);
      case ShapeOp::level_set:
        return level_sets[node.level_set].view().probe_phi(y);
      default:
        return Real(0);  // not a leaf: never reached for a program compile() produced
    }
  }
};

static_assert(std::is_trivially_copyable_v<ShapeView<3>> && std::is_trivially_copyable_v<ShapeView<2>>,
              "a shape view is captured by value into kernels, so it must be trivially copyable.");

}  // namespace unisph::shape
