#pragma once
// One instruction of a compiled shape (compiled_shape.hpp): shapes are evaluated inside kernels
// as a postfix program over a small stack of signed distances. Leaves push the signed distance of
// a primitive or of a level set at the query point; booleans pop two values and push one; shell
// and complement change the top value.
//
// Every rigid transform and uniform scale of the host tree is folded into the leaves when the
// tree is compiled: a leaf maps the world point x to its own frame, y = to_local (x - origin) /
// scale, and its world distance is scale times its local one. So the program itself holds no
// transform nodes and a leaf costs one small matrix product more only when it was transformed.

#include <cstdint>
#include <type_traits>

#include "unisph/core/config.hpp"
#include "unisph/core/vector.hpp"

namespace unisph::shape {

enum class ShapeOp : std::uint32_t {
  // leaves
  box,         // a: centre, b: half extents
  sphere,      // a: centre, radius (a circle in 2D)
  cylinder,    // 3D: a: one end of the axis, b: unit axis, length, radius
  half_space,  // a: a point of the plane, b: unit outward normal (solid where dot(x - a, b) < 0)
  level_set,   // level_set: index into the compiled shape's table of level-set views
  // operations on the stack
  unite,       // min(a, b)
  intersect,   // max(a, b)
  subtract,    // max(a, -b): a without b
  shell,       // |a| - radius: the band of thickness 2 radius around a's surface
  complement,  // -a: everything outside a
};

UNISPH_HOST_DEVICE constexpr bool is_leaf(ShapeOp op) { return op <= ShapeOp::level_set; }

template <int D>
struct ShapeNode {
  ShapeOp op;
  std::uint32_t level_set;  // for ShapeOp::level_set
  bool transformed;         // false: to_local, origin and scale are the identity and are skipped
  Mat<Real, D> to_local;    // rotation from the world frame to the leaf's frame
  Vec<Real, D> origin;      // where the leaf's frame origin lies in the world
  Real scale;               // world length per local length (> 0)
  Vec<Real, D> a, b;        // the primitive's points and directions (see ShapeOp)
  Real length;              // cylinder: axis length
  Real radius;              // sphere, cylinder: radius; shell: half thickness (world units)
};

static_assert(std::is_trivially_copyable_v<ShapeNode<3>> && std::is_trivially_copyable_v<ShapeNode<2>>,
              "shape nodes are copied to the device byte for byte, so they must be trivially copyable.");

}  // namespace unisph::shape
