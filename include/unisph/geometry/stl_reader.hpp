#pragma once
// Reading STL files, binary and ASCII, into raw facets (no welding, no repair: see mesh_repair.hpp).
//
// The format is decided by size and content, never by the first word: a binary file whose
// 80-byte header begins with "solid" is common. A file is binary when its size is exactly
// 84 + 50 * (the count at byte 80) and it is not entirely text; it is ASCII when it begins
// with "solid" and is entirely text. ASCII files may hold several `solid` blocks, CRLF line
// ends, keywords in any case and numbers with exponents.
//
// Any defect (truncation, a count that disagrees with the size, a non-finite coordinate,
// text where a number belongs, a file that is not STL) throws GeometryError with one line
// "<file>: <what is wrong>". A file with no facets is valid and gives an empty result.

#include <span>
#include <string>
#include <vector>

#include "unisph/geometry/geometry_error.hpp"
#include "unisph/geometry/triangle_mesh.hpp"

namespace unisph {

struct StlFacets {
  bool binary = false;
  std::size_t solids = 0;  // 1 for binary files
  std::vector<RawTriangle> facets;
};

// Parses the bytes of an STL file; `source` names it in error messages.
StlFacets parse_stl(std::span<const unsigned char> bytes, const std::string& source);

// Reads and parses a file; an unreadable file is a GeometryError as well.
StlFacets read_stl(const std::string& path);

}  // namespace unisph
