#pragma once
// Views over a variable defined on the packages of a sparse grid (grid/package_mesh.hpp): the
// data packages, and one level down the 4^D data points of each (issue 8, part 3).
//
//   DataPackages<Value, D>   the data packages (index >= far_field_packages, as package_for),
//                            random access; child: PackagePoints
//   PackagePoints<Value, D>  the 4^D data points of one package, a compile-time count (like a
//                            frame's slots), all of them valid
//
// and the same hierarchy without a variable, where slots name places instead of pointing at values
// (ValueSlot, slot_ref.hpp): what package_for and data_point_for walk (grid/package_for.hpp)
//
//   PackagesOfMesh<D>        a run of data packages of a mesh (of(mesh): all of them, index >=
//                            far_field_packages; part(offset, n): n of them), random access; slot:
//                            the package index (std::uint32_t); child: PackageDataPoints
//   PackageDataPoints<D>     the 4^D data points of one package; slot: its DataPointAddress
//                            (package, local point); under a padding position of the packages
//                            (empty_handle(): no points) 4^D empty slots, so team walks stay in step
//
// Values of package p sit at values[p * 4^D .. (p + 1) * 4^D) (package_mesh.hpp). A package's own
// element (what a package-level view yields without a Child) is its first data point.
// data_point_of() turns a slot back into (package, local point), the arguments data_point_for
// gives its kernels:
//
//   using Points = iter::View<iter::PackagePoints<Real, 3>>;
//   iter::View<iter::DataPackages<Real, 3>, direction::Forward, collectivity::None, RuntimeTuple, Points>
//       view(iter::DataPackages<Real, 3>{field.data(), mesh.packages()}, RuntimeTuple{}, Points(nullptr));
//   view.for_each([&](iter::SlotRef<Real> slot) { const DataPointAddress a = iter::data_point_of(field.data(), slot); ... });

#include <cstdint>
#include <type_traits>

#include "unisph/core/config.hpp"
#include "unisph/grid/neighbour_index_shift.hpp"
#include "unisph/grid/package_grid.hpp"
#include "unisph/iter/container_traits.hpp"
#include "unisph/iter/slot_ref.hpp"

namespace unisph::iter {

// Far-field packages (0: outside, 1: inside) come first and hold no data of their own that loops visit.
inline constexpr Index first_data_package = 2;

template <class Value, int D>
struct PackagePoints {
  Value* points = nullptr;  // the package's 4^D values; null: an empty package (padding)
};

template <class Value, int D>
struct DataPackages {
  Value* values = nullptr;  // packages * 4^D values
  Index packages = 0;       // every package, the far-field ones included (PackageMesh::packages())
};

// The package and local point of a slot of a view over `values`.
template <class Value, int D>
UNISPH_HOST_DEVICE inline DataPointAddress data_point_of(const Value* values, SlotRef<Value> slot) {
  const Index global = Index(slot.get() - values);
  return {std::uint32_t(global / package_points<D>), int(global % package_points<D>)};
}

template <class Value, int D>
struct ContainerTraits<PackagePoints<Value, D>> : RandomAccessNavigation {
  using Handle = PackagePoints<Value, D>;
  using Component = Value;
  static constexpr bool needs_runtime_size = false;
  static constexpr Index number_of_elements = package_points<D>;

  UNISPH_HOST_DEVICE static constexpr Handle empty_handle() { return Handle{}; }
  UNISPH_HOST_DEVICE static constexpr Cursor start(const Handle&, Index position, bool forward) {
    return start_at(package_points<D>, position, forward);
  }
  UNISPH_HOST_DEVICE static constexpr Cursor step(const Handle&, Cursor cursor, Index k, bool forward) {
    return step_by(cursor, k, forward);
  }
  UNISPH_HOST_DEVICE static constexpr bool holds_element(const Handle& h, Cursor) { return h.points != nullptr; }
  // Every point of a package holds a value: View::for_each walks them without a test.
  UNISPH_HOST_DEVICE static constexpr Index filled_prefix(const Handle& h) {
    return h.points != nullptr ? Index(package_points<D>) : 0;
  }
  UNISPH_HOST_DEVICE static constexpr Index slot_count(const Handle&) { return package_points<D>; }
  UNISPH_HOST_DEVICE static constexpr Component& element(const Handle& h, Cursor point) { return h.points[point]; }
};

template <class Value, int D>
struct ContainerTraits<DataPackages<Value, D>> : RandomAccessNavigation {
  using Handle = DataPackages<Value, D>;
  using Component = Value;  // the package's first data point
  using ChildContainer = PackagePoints<Value, D>;
  static constexpr bool needs_runtime_size = true;

  UNISPH_HOST_DEVICE static constexpr Handle empty_handle() { return Handle{}; }
  UNISPH_HOST_DEVICE static constexpr Index size(const Handle& h) {
    return h.packages > first_data_package ? h.packages - first_data_package : 0;
  }
  // The cursor is the package index.
  UNISPH_HOST_DEVICE static constexpr Cursor start(const Handle& h, Index position, bool forward) {
    return first_data_package + start_at(size(h), position, forward);
  }
  UNISPH_HOST_DEVICE static constexpr Cursor step(const Handle&, Cursor cursor, Index k, bool forward) {
    return step_by(cursor, k, forward);
  }
  UNISPH_HOST_DEVICE static constexpr bool holds_element(const Handle&, Cursor) { return true; }
  UNISPH_HOST_DEVICE static constexpr Component& element(const Handle& h, Cursor package) {
    return h.values[package * package_points<D>];
  }
  UNISPH_HOST_DEVICE static constexpr ChildContainer child(const Handle& h, Cursor package) {
    return {h.values + package * package_points<D>};
  }
};

static_assert(std::is_trivially_copyable_v<DataPackages<double, 3>> && std::is_trivially_copyable_v<PackagePoints<float, 2>>);

// ---- the hierarchy itself: packages and data points named by index -----------------------------

// No package: the handle of the data points under a padding position.
inline constexpr std::uint32_t no_package = ~std::uint32_t(0);

template <int D>
struct PackageDataPoints {
  static_assert(D == 2 || D == 3, "iter::PackageDataPoints<D>: packages of a sparse grid are 2D (4^2 points) or 3D (4^3).");
  std::uint32_t package = no_package;  // the package whose points these are
  std::uint32_t points = 0;            // 4^D for a package, 0 under a padding position (empty_handle())

  // The data points of `package`.
  UNISPH_HOST_DEVICE static constexpr PackageDataPoints of(std::uint32_t package) {
    return PackageDataPoints{package, std::uint32_t(package_points<D>)};
  }
};

// A run of data packages of a mesh: packages first .. first + count - 1.
template <int D>
struct PackagesOfMesh {
  static_assert(D == 2 || D == 3, "iter::PackagesOfMesh<D>: packages of a sparse grid are 2D or 3D.");
  Index first = first_data_package;
  Index count = 0;

  // Every data package of `mesh` (a PackageMesh<D>, or anything with data_packages()).
  template <class Mesh>
  static PackagesOfMesh of(const Mesh& mesh) {
    static_assert(Mesh::dimension == D, "iter::PackagesOfMesh<D>::of(mesh): the mesh has another dimension.");
    return PackagesOfMesh{first_data_package, mesh.data_packages()};
  }
  // The `n` packages from the one `offset` places on (the caller keeps offset + n within count).
  UNISPH_HOST_DEVICE constexpr PackagesOfMesh part(Index offset, Index n) const { return PackagesOfMesh{first + offset, n}; }
};

template <int D>
struct ContainerTraits<PackageDataPoints<D>> : RandomAccessNavigation {
  using Handle = PackageDataPoints<D>;
  using Component = DataPointAddress;
  static constexpr bool needs_runtime_size = false;
  static constexpr Index number_of_elements = package_points<D>;
  static constexpr bool small_positions = true;

  UNISPH_HOST_DEVICE static constexpr Handle empty_handle() { return Handle{}; }
  // The cursor is the local point number.
  UNISPH_HOST_DEVICE static constexpr Cursor start(const Handle&, Index position, bool forward) {
    return start_at(package_points<D>, position, forward);
  }
  UNISPH_HOST_DEVICE static constexpr Cursor step(const Handle&, Cursor cursor, Index k, bool forward) {
    return step_by(cursor, k, forward);
  }
  UNISPH_HOST_DEVICE static constexpr bool holds_element(const Handle& h, Cursor point) { return point < h.points; }
  // All 4^D points of a package (a compile-time 4^D where the handle comes from child()), none
  // under a padding position: View::for_each walks them without a test.
  UNISPH_HOST_DEVICE static constexpr Index filled_prefix(const Handle& h) { return h.points; }
  UNISPH_HOST_DEVICE static constexpr Index slot_count(const Handle&) { return package_points<D>; }
  UNISPH_HOST_DEVICE static constexpr ValueSlot<DataPointAddress> slot(const Handle& h, Cursor point) {
    return ValueSlot<DataPointAddress>::of(DataPointAddress{h.package, int(point)});
  }
};

template <int D>
struct ContainerTraits<PackagesOfMesh<D>> : RandomAccessNavigation {
  using Handle = PackagesOfMesh<D>;
  using Component = std::uint32_t;  // the package index
  using ChildContainer = PackageDataPoints<D>;
  static constexpr bool needs_runtime_size = true;
  // Package indices are 32-bit (PackageMesh::allocate refuses more).
  static constexpr bool small_positions = true;
  static constexpr bool every_slot_filled = true;

  UNISPH_HOST_DEVICE static constexpr Handle empty_handle() { return Handle{}; }
  UNISPH_HOST_DEVICE static constexpr Index size(const Handle& h) { return h.count; }
  // The cursor is the package index.
  UNISPH_HOST_DEVICE static constexpr Cursor start(const Handle& h, Index position, bool forward) {
    return h.first + start_at(h.count, position, forward);
  }
  UNISPH_HOST_DEVICE static constexpr Cursor step(const Handle&, Cursor cursor, Index k, bool forward) {
    return step_by(cursor, k, forward);
  }
  UNISPH_HOST_DEVICE static constexpr bool holds_element(const Handle&, Cursor) { return true; }
  UNISPH_HOST_DEVICE static constexpr ValueSlot<std::uint32_t> slot(const Handle&, Cursor package) {
    return ValueSlot<std::uint32_t>::of(std::uint32_t(package));
  }
  UNISPH_HOST_DEVICE static constexpr ChildContainer child(const Handle&, Cursor package) {
    return ChildContainer::of(std::uint32_t(package));
  }
};

static_assert(std::is_trivially_copyable_v<PackagesOfMesh<3>> && std::is_trivially_copyable_v<PackageDataPoints<2>>);

}  // namespace unisph::iter
