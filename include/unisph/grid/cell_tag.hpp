#pragma once
// What a cell of a package grid is, before and after packages are allocated.
//
//   CellTag (one per cell, written by whoever decides where data is needed):
//     outside, inside   no package: the cell takes the far-field package of that side
//     inner, core       a package of its own; core cells hold the interface, inner ones
//                       surround the core so that stencils around the core find data
//   PackageType (one per package): the two far-field packages, then inner and core ones.

#include <cstdint>

namespace unisph {

enum class CellTag : std::uint8_t { outside = 0, inside = 1, inner = 2, core = 3 };

enum class PackageType : std::uint8_t { far_field = 0, inner = 2, core = 3 };

inline constexpr bool has_package(CellTag tag) { return tag == CellTag::inner || tag == CellTag::core; }

// Packages 0 and 1 are the far-field packages: every cell outside (inside) the band points to
// them, and their neighbours are themselves, so stencils that leave the band stay defined.
inline constexpr std::uint32_t outside_package = 0;
inline constexpr std::uint32_t inside_package = 1;
inline constexpr std::uint32_t far_field_packages = 2;

}  // namespace unisph
