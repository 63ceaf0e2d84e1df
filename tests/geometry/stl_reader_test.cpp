// STL reading: formats decided by size and content, ASCII variants, and one one-line error per defect.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "test_data.hpp"
#include "unisph/geometry/mesh_repair.hpp"
#include "unisph/geometry/stl_reader.hpp"

namespace {
using namespace unisph;
using unisph::testing::test_data;

std::vector<unsigned char> file_bytes(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}
std::vector<unsigned char> text_bytes(const std::string& text) { return {text.begin(), text.end()}; }

// The message of the GeometryError that parsing `bytes` throws ("" when nothing is thrown).
std::string parse_error(const std::vector<unsigned char>& bytes, const std::string& source = "broken.stl") {
  try {
    parse_stl(bytes, source);
  } catch (const GeometryError& e) {
    return e.what();
  }
  return "";
}

// Every error is one line that begins with the file's name.
void expect_one_line_error(const std::string& message, const std::string& source, const std::string& phrase) {
  ASSERT_FALSE(message.empty()) << "no error was thrown; expected one mentioning '" << phrase << "'";
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_EQ(message.rfind(source + ": ", 0), 0u) << message;
  EXPECT_NE(message.find(phrase), std::string::npos) << message;
}

const char* const ascii_tetrahedron =
    "solid tetra\r\n"
    "  FACET NORMAL 0 0 0\r\n    OUTER LOOP\r\n      VERTEX 0 0 0\r\n      VERTEX 0 1.0E+00 0\r\n"
    "      VERTEX 1e0 0 0\r\n    ENDLOOP\r\n  ENDFACET\r\n"
    "  facet normal 0 0 0\n outer loop\n vertex 0 0 0\n vertex +1.0 0 0\n vertex 0 0 10E-1\n endloop\n endfacet\n"
    "  facet normal 0 0 0\n outer loop\n vertex 0 0 0\n vertex 0 0 1\n vertex 0 1 0\n endloop\n endfacet\n"
    "  facet normal 0 0 0\n outer loop\n vertex 1 0 0\n vertex 0 1 0\n vertex 0 0 1\n endloop\n endfacet\n"
    "endsolid tetra\r\n";

TEST(HostStlReader, ReadsEveryTestMeshWithItsFacetCount) {
  struct Expected {
    const char* file;
    std::size_t facets;
    bool binary;
  };
  const Expected expected[] = {
      {"triangle_prism.stl", 8, true},          {"SPHinXsys.stl", 364, true},
      {"barrel.stl", 640, true},                {"teapot.stl", 9438, true},
      {"trimesh_teapot.stl", 894, true},        {"trimesh_unit_sphere.stl", 1280, true},
      {"trimesh_cylinder.stl", 416, true},      {"trimesh_20mm-xyz-cube.stl", 260, true},
      {"trimesh_plate_holes.stl", 1252, true},  {"trimesh_multibody.stl", 32, false},
      {"trimesh_two_objects_mixed_case_names.stl", 24, false}, {"trimesh_soup.stl", 100, true},
  };
  for (const Expected& e : expected) {
    const StlFacets facets = read_stl(test_data(std::string("geometry/") + e.file));
    EXPECT_EQ(facets.facets.size(), e.facets) << e.file;
    EXPECT_EQ(facets.binary, e.binary) << e.file;
  }
}

TEST(HostStlReader, BinaryFileWhoseHeaderBeginsWithSolidIsBinary) {
  const std::vector<unsigned char> bytes = file_bytes(test_data("geometry/trimesh_plate_holes.stl"));
  ASSERT_EQ(std::memcmp(bytes.data(), "solid", 5), 0);
  const StlFacets facets = parse_stl(bytes, "plate");
  EXPECT_TRUE(facets.binary);
  EXPECT_EQ(facets.facets.size(), 1252u);
}

TEST(HostStlReader, AsciiWithSeveralSolidsCrlfAndExponents) {
  const StlFacets two = read_stl(test_data("geometry/trimesh_two_objects_mixed_case_names.stl"));
  EXPECT_EQ(two.solids, 2u);
  const StlFacets multibody = read_stl(test_data("geometry/trimesh_multibody.stl"));  // CRLF, E-014 exponents
  EXPECT_FALSE(multibody.binary);
  EXPECT_GE(multibody.solids, 1u);

  const StlFacets tetra = parse_stl(text_bytes(ascii_tetrahedron), "tetra");
  ASSERT_EQ(tetra.facets.size(), 4u);
  EXPECT_EQ(tetra.facets[0].corner[1][1], 1.0);
  EXPECT_EQ(tetra.facets[0].corner[2][0], 1.0);
  EXPECT_EQ(tetra.facets[1].corner[1][0], 1.0);
  EXPECT_EQ(tetra.facets[1].corner[2][2], 1.0);
}

TEST(HostStlReader, AsciiWithNulPaddingOrEndOfFileMark) {
  std::vector<unsigned char> bytes = text_bytes(ascii_tetrahedron);
  bytes.push_back(0x1a);
  EXPECT_EQ(parse_stl(bytes, "dos").facets.size(), 4u);
  bytes.insert(bytes.end(), 7, 0);
  EXPECT_EQ(parse_stl(bytes, "padded").facets.size(), 4u);
}

TEST(HostStlReader, EmptyMeshesAreReadAndRefusedWhereTrianglesAreNeeded) {
  for (const char* file : {"geometry/bad/empty_ascii.stl", "geometry/bad/empty_binary.stl"}) {
    const LoadedMesh loaded = load_triangle_mesh(test_data(file));
    EXPECT_TRUE(loaded.mesh.empty()) << file;
    EXPECT_EQ(loaded.report.facets_read, 0u);
    try {
      require_triangles(loaded.mesh, "a distance query");
      ADD_FAILURE() << "an empty mesh was accepted";
    } catch (const GeometryError& e) {
      expect_one_line_error(e.what(), test_data(file), "has no triangles; a distance query needs at least one");
    }
  }
}

TEST(HostStlReader, TruncatedBinaryFile) {
  std::vector<unsigned char> bytes = file_bytes(test_data("geometry/teapot.stl"));
  bytes.resize(bytes.size() - 30);
  expect_one_line_error(parse_error(bytes), "broken.stl", "truncated binary STL");
}

TEST(HostStlReader, BinaryCountThatDisagreesWithTheSize) {
  std::vector<unsigned char> bytes = file_bytes(test_data("geometry/triangle_prism.stl"));
  bytes[80] = 7;  // the file holds 8 facets
  expect_one_line_error(parse_error(bytes), "broken.stl", "disagrees with the size");
}

TEST(HostStlReader, NonFiniteCoordinateInBinaryFile) {
  std::vector<unsigned char> bytes = file_bytes(test_data("geometry/triangle_prism.stl"));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(bytes.data() + 84 + 50 * 3 + 12 + 4, &nan, 4);  // facet 3, corner 0, y
  expect_one_line_error(parse_error(bytes), "broken.stl", "facet 3 has a non-finite coordinate");
}

TEST(HostStlReader, NonFiniteCoordinateInAsciiFile) {
  std::string text = ascii_tetrahedron;
  text.replace(text.find("vertex +1.0"), 11, "vertex inf");
  expect_one_line_error(parse_error(text_bytes(text)), "broken.stl", "line 12: non-finite vertex coordinate 'inf'");
  text = ascii_tetrahedron;
  text.replace(text.find("vertex +1.0"), 11, "vertex NaN");
  expect_one_line_error(parse_error(text_bytes(text)), "broken.stl", "non-finite vertex coordinate 'NaN'");
}

TEST(HostStlReader, NonFiniteStoredNormalsAreIgnored) {
  // Exporters write "nan" normals for degenerate facets; normals are never used, so that is no error.
  std::string text = ascii_tetrahedron;
  text.replace(text.find("FACET NORMAL 0 0 0"), 18, "FACET NORMAL nan -inf NaN");
  EXPECT_EQ(parse_stl(text_bytes(text), "normals").facets.size(), 4u);
  text.replace(text.find("FACET NORMAL nan"), 16, "FACET NORMAL abc");
  expect_one_line_error(parse_error(text_bytes(text)), "broken.stl", "expected a number (normal component), found 'abc'");
}

TEST(HostStlReader, TextWhereANumberBelongs) {
  std::string text = ascii_tetrahedron;
  text.replace(text.find("vertex +1.0"), 11, "vertex 1.0x");
  expect_one_line_error(parse_error(text_bytes(text)), "broken.stl", "line 12: expected a number (vertex coordinate), found '1.0x'");
}

TEST(HostStlReader, TruncatedAsciiFile) {
  std::string text = ascii_tetrahedron;
  text.resize(text.find("endsolid"));
  expect_one_line_error(parse_error(text_bytes(text)), "broken.stl", "'endsolid' is missing");
  text.resize(text.rfind("endloop"));
  expect_one_line_error(parse_error(text_bytes(text)), "broken.stl", "ends early");
}

TEST(HostStlReader, AsciiKeywordOutOfPlace) {
  std::string text = ascii_tetrahedron;
  text.replace(text.find("outer loop"), 10, "outer lop");
  expect_one_line_error(parse_error(text_bytes(text)), "broken.stl", "expected 'loop', found 'lop'");
}

TEST(HostStlReader, FilesThatAreNotStl) {
  expect_one_line_error(parse_error({}), "broken.stl", "the file is empty");
  expect_one_line_error(parse_error(text_bytes("hello, world\n")), "broken.stl", "not an STL file");
  std::vector<unsigned char> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  png.resize(5000, 0x42);
  expect_one_line_error(parse_error(png), "broken.stl", "not an STL file");
  expect_one_line_error(parse_error(text_bytes(std::string(200, 'x'))), "broken.stl", "not an STL file");
}

TEST(HostStlReader, SolidHeaderWithBinaryBytesAndAWrongCount) {
  std::vector<unsigned char> bytes = file_bytes(test_data("geometry/trimesh_plate_holes.stl"));
  bytes.resize(bytes.size() - 50);
  expect_one_line_error(parse_error(bytes), "broken.stl", "begins with 'solid' but is not ASCII STL");
}

TEST(HostStlReader, MissingFile) {
  try {
    read_stl("/nonexistent/part.stl");
    ADD_FAILURE() << "no error";
  } catch (const GeometryError& e) {
    expect_one_line_error(e.what(), "/nonexistent/part.stl", "cannot open the file");
  }
}

}  // namespace
