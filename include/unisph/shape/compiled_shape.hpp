#pragma once
// A shape compiled for kernels: the tree flattened into a postfix program of trivially copyable
// nodes (shape_node.hpp) in a DiscreteVariable, the transforms folded into the leaves, and a
// table of the level-set views its geometry-file leaves probe, one per memory space.
//
//   shape::CompiledShape<3> solid(tank);                 // throws ShapeError for an empty or too deep tree
//   particle_for(policy, n, Kernel{solid.view(policy), ...});
//
// Any number of geometry files may appear (the views' table is an array in memory, not in the
// kernel's parameters); the limit is the evaluation stack (max_shape_stack, shape_view.hpp).

#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "unisph/core/box.hpp"
#include "unisph/exec/policy.hpp"
#include "unisph/memory/discrete_variable.hpp"
#include "unisph/shape/shape.hpp"
#include "unisph/shape/shape_view.hpp"

namespace unisph::shape {

template <int D>
class CompiledShape {
 public:
  explicit CompiledShape(const Shape<D>& shape) {
    if (shape.empty()) throw ShapeError("shape: cannot compile an empty shape");
    std::vector<ShapeNode<D>> program;
    const Flattened root = flatten(shape.node(), detail::Similarity<D>{}, program);
    if (root.stack > max_shape_stack)
      throw ShapeError("shape: the tree needs an evaluation stack of " + std::to_string(root.stack) +
                       " entries, more than the " + std::to_string(max_shape_stack) +
                       " a kernel holds; build long unions and intersections with union_of / intersection_of of a "
                       "list (balanced), or put the deep operand on the left");
    stack_ = root.stack;
    bounds_ = root.bounds;
    program_.assign(program);
  }

  template <ExecutionPolicy P>
  ShapeView<D> view(P policy) {
    return {program_.read(policy), level_set_views(policy)};
  }

  Index program_size() const { return program_.size(); }
  int stack_depth() const { return stack_; }
  Index geometry_files() const { return geometries_.size(); }
  // An axis-aligned box holding the solid (conservative for rotated and curved parts); infinite
  // along an axis where the solid is unbounded (half-spaces, complements).
  const Box<Real, D>& bounds() const { return bounds_; }
  bool bounded() const {
    for (int k = 0; k < D; ++k)
      if (!std::isfinite(bounds_.lower[k]) || !std::isfinite(bounds_.upper[k])) return false;
    return true;
  }

 private:
  struct Flattened {
    int stack;
    Box<Real, D> bounds;
  };
  using Node = ShapeTreeNode<D>;
  using Kind = typename Node::Kind;

  static Box<Real, D> everywhere() {
    const Real inf = std::numeric_limits<Real>::infinity();
    return {Vec<Real, D>::constant(-inf), Vec<Real, D>::constant(inf)};
  }
  static bool finite(const Box<Real, D>& b) {
    for (int k = 0; k < D; ++k)
      if (!std::isfinite(b.lower[k]) || !std::isfinite(b.upper[k])) return false;
    return true;
  }
  // The world box of a local box under a similarity: the box of its transformed corners.
  static Box<Real, D> to_world(const Box<Real, D>& local, const detail::Similarity<D>& map) {
    if (map.identity) return local;
    if (!finite(local)) return everywhere();
    Box<Real, D> world{Vec<Real, D>::constant(std::numeric_limits<Real>::max()),
                       Vec<Real, D>::constant(-std::numeric_limits<Real>::max())};
    for (int corner = 0; corner < (1 << D); ++corner) {
      Vec<Real, D> c;
      for (int k = 0; k < D; ++k) c[k] = (corner >> k) & 1 ? local.upper[k] : local.lower[k];
      const Vec<Real, D> x = map.apply(c);
      world.lower = min(world.lower, x);
      world.upper = max(world.upper, x);
    }
    return world;
  }

  Flattened flatten(const Node& node, const detail::Similarity<D>& map, std::vector<ShapeNode<D>>& program) {
    switch (node.kind) {
      case Kind::leaf: {
        ShapeNode<D> leaf = node.leaf;
        leaf.transformed = !map.identity;
        leaf.to_local = transpose(map.rotation);
        leaf.origin = map.translation;
        leaf.scale = map.scale;
        if (leaf.op == ShapeOp::level_set) leaf.level_set = geometry_index(node.geometry);
        program.push_back(leaf);
        return {1, to_world(local_bounds(node), map)};
      }
      case Kind::transform:
        return flatten(node.operands[0].node(), map.after(node.transform), program);
      case Kind::shell:
      case Kind::complement: {
        Flattened inner = flatten(node.operands[0].node(), map, program);
        ShapeNode<D> op{};
        op.op = node.kind == Kind::shell ? ShapeOp::shell : ShapeOp::complement;
        op.radius = node.half_thickness * map.scale;  // the thickness scales with its operand
        program.push_back(op);
        if (node.kind == Kind::complement) return {inner.stack, everywhere()};
        Box<Real, D> b = inner.bounds;
        b.lower -= Vec<Real, D>::constant(op.radius);
        b.upper += Vec<Real, D>::constant(op.radius);
        return {inner.stack, b};
      }
      default: {
        const Flattened a = flatten(node.operands[0].node(), map, program);
        const Flattened b = flatten(node.operands[1].node(), map, program);
        ShapeNode<D> op{};
        op.op = node.kind == Kind::unite ? ShapeOp::unite : node.kind == Kind::intersect ? ShapeOp::intersect
                                                                                         : ShapeOp::subtract;
        program.push_back(op);
        // The left value waits on the stack while the right operand is evaluated.
        const int stack = a.stack > b.stack + 1 ? a.stack : b.stack + 1;
        Box<Real, D> bounds = a.bounds;
        if (node.kind == Kind::unite) {
          bounds = {min(a.bounds.lower, b.bounds.lower), max(a.bounds.upper, b.bounds.upper)};
        } else if (node.kind == Kind::intersect) {
          bounds = {max(a.bounds.lower, b.bounds.lower), min(a.bounds.upper, b.bounds.upper)};
        }
        return {stack, bounds};
      }
    }
  }

  static Box<Real, D> local_bounds(const Node& node) {
    const ShapeNode<D>& n = node.leaf;
    switch (n.op) {
      case ShapeOp::box:
        return {n.a - n.b, n.a + n.b};
      case ShapeOp::sphere:
        return {n.a - Vec<Real, D>::constant(n.radius), n.a + Vec<Real, D>::constant(n.radius)};
      case ShapeOp::cylinder: {
        const Vec<Real, D> end = n.a + n.b * n.length;
        return {min(n.a, end) - Vec<Real, D>::constant(n.radius), max(n.a, end) + Vec<Real, D>::constant(n.radius)};
      }
      case ShapeOp::level_set:
        return {node.geometry->lower(), node.geometry->upper()};
      default:
        return everywhere();
    }
  }

  std::uint32_t geometry_index(const std::shared_ptr<MeshLevelSet<D>>& geometry) {
    for (std::size_t i = 0; i < geometries_.size(); ++i)
      if (geometries_[i] == geometry) return std::uint32_t(i);
    geometries_.push_back(geometry);
    return std::uint32_t(geometries_.size() - 1);
  }

  // The level-set views of every geometry file, valid in P's memory space: written on the host
  // once per space (the device table holds device pointers and is only read there).
  template <ExecutionPolicy P>
  View<const LevelSetViewStorage<D>> level_set_views(P policy) {
    const bool device = P::space == MemorySpace::device;
    DiscreteVariable<LevelSetViewStorage<D>>& table = device ? device_views_ : host_views_;
    bool& filled = device ? device_filled_ : host_filled_;
    if (!filled && !geometries_.empty()) {
      std::vector<LevelSetViewStorage<D>> views(geometries_.size());
      for (std::size_t i = 0; i < geometries_.size(); ++i) {
        const MultiResolutionLevelSetView<D> view = geometries_[i]->level_set().view(policy);
        std::memcpy(views[i].bytes, &view, sizeof view);
      }
      table.assign(views);
      filled = true;
    }
    return table.read(policy);
  }

  DiscreteVariable<ShapeNode<D>> program_{"ShapeProgram"};
  std::vector<std::shared_ptr<MeshLevelSet<D>>> geometries_;
  DiscreteVariable<LevelSetViewStorage<D>> host_views_{"ShapeLevelSetViewsHost"};
  DiscreteVariable<LevelSetViewStorage<D>> device_views_{"ShapeLevelSetViewsDevice"};
  bool host_filled_ = false, device_filled_ = false;
  int stack_ = 0;
  Box<Real, D> bounds_{};
};

}  // namespace unisph::shape
