#pragma once
// The geometry a level set is built from, by dimension: a triangle mesh in 3D, polygons in 2D.
// Both views answer nearest(p) (squared distance to the surface) and sign(p, nearest) (+1
// outside, -1 inside) in kernels on every policy.

#include <type_traits>

#include "unisph/geometry/polygon_search.hpp"
#include "unisph/geometry/triangle_mesh_search.hpp"

namespace unisph {

template <int D>
using ShapeSearch = std::conditional_t<D == 3, TriangleMeshSearch, PolygonSearch>;
template <int D>
using ShapeSearchView = std::conditional_t<D == 3, TriangleMeshSearchView, PolygonSearchView>;

}  // namespace unisph

namespace unisph {

template <class SearchView>
struct WindingNumberSign;

// Shapes that search a triangle mesh: triangle_mesh_of(shape) is its TriangleMeshSearchView, so
// kernels may query the mesh for a batch of points at once (triangle_batch_nearest.hpp) and still
// answer what shape.nearest would.
template <class Shape>
inline constexpr bool searches_triangle_mesh = false;
template <>
inline constexpr bool searches_triangle_mesh<TriangleMeshSearchView> = true;
template <>
inline constexpr bool searches_triangle_mesh<WindingNumberSign<TriangleMeshSearchView>> = true;

// Shapes whose sign is the triangle mesh's winding number (so that kernels may decide it for a
// batch of points at once, triangle_batch_winding.hpp).
template <class Shape>
inline constexpr bool signs_by_winding_number = false;
template <>
inline constexpr bool signs_by_winding_number<WindingNumberSign<TriangleMeshSearchView>> = true;

UNISPH_HOST_DEVICE inline const TriangleMeshSearchView& triangle_mesh_of(const TriangleMeshSearchView& s) { return s; }
UNISPH_HOST_DEVICE inline const TriangleMeshSearchView& triangle_mesh_of(const WindingNumberSign<TriangleMeshSearchView>& s);

// A shape search signed by the generalized winding number (inside where it exceeds 1/2)
// instead of the pseudonormal of the nearest feature: right also where a closed mesh overlaps
// itself or holds inner walls (the pseudonormal of an inner wall points into the solid), and
// where a leaking mesh's holes make the pseudonormal of the rim meaningless; about twice the
// work per point.
template <class SearchView>
struct WindingNumberSign {
  SearchView search;
  template <class Point>
  UNISPH_HOST_DEVICE auto nearest(const Point& p) const {
    return search.nearest(p);
  }
  template <class Point, class Nearest>
  UNISPH_HOST_DEVICE int sign(const Point& p, const Nearest&) const {
    return search.winding_number(p) > Real(0.5) ? -1 : 1;
  }
};

UNISPH_HOST_DEVICE inline const TriangleMeshSearchView& triangle_mesh_of(const WindingNumberSign<TriangleMeshSearchView>& s) {
  return s.search;
}

}  // namespace unisph
