#pragma once
// Binary VTK XML output that ParaView and VTK read: PolyData (.vtp) files of points with point
// arrays, raw appended data with 64-bit block headers, and the ParaView collection (.pvd)
// that lists them by time. Every file is written to "<name>.tmp" and renamed, so a reader
// (or a crash) never sees half a file. Host code only.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <type_traits>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "unisph/core/error.hpp"

namespace unisph::io {

struct PointArray {
  std::string name;
  std::string vtk_type;  // Float32, Float64, UInt64, ...
  int components = 1;
  std::vector<unsigned char> bytes;

  template <class S>
  static PointArray from(std::string name, int components, const std::vector<S>& values) {
    PointArray a{std::move(name), vtk_type_of<S>(), components, {}};
    a.bytes.resize(values.size() * sizeof(S));
    if (!values.empty()) std::memcpy(a.bytes.data(), values.data(), a.bytes.size());
    return a;
  }
  template <class S>
  static std::string vtk_type_of() {
    if constexpr (std::is_same_v<S, float>) return "Float32";
    else if constexpr (std::is_same_v<S, double>) return "Float64";
    else if constexpr (std::is_same_v<S, std::uint64_t>) return "UInt64";
    else if constexpr (std::is_same_v<S, std::int64_t>) return "Int64";
    else static_assert(sizeof(S) == 0, "VTK arrays are written for float, double, uint64 and int64 values.");
  }
};

// Writes `text` (or bytes) to path via a temporary file and a rename.
inline void write_file_atomically(const std::filesystem::path& path, const std::string& content) {
  const std::filesystem::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error("cannot write " + tmp.string());
    out.write(content.data(), std::streamsize(content.size()));
    if (!out) throw Error("writing " + tmp.string() + " failed");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw Error("cannot rename " + tmp.string() + " to " + path.string() + ": " + ec.message());
}

// points: three coordinates per point (2D cases pass z = 0), in the type S of `points`.
// field_arrays: values of the whole data set (VTK's FieldData, e.g. the spacing of a generated
// particle set), each a `components`-tuple array.
template <class S>
void write_vtp(const std::filesystem::path& path, const std::vector<S>& points, const std::vector<PointArray>& arrays,
               const std::vector<PointArray>& field_arrays = {}) {
  const std::uint64_t n = points.size() / 3;
  std::vector<std::int64_t> connectivity(n), offsets(n);
  for (std::uint64_t i = 0; i < n; ++i) {
    connectivity[i] = std::int64_t(i);
    offsets[i] = std::int64_t(i + 1);
  }
  std::ostringstream xml, data;
  std::uint64_t offset = 0;
  auto block = [&](const void* bytes, std::uint64_t size) {
    const std::uint64_t at = offset;
    data.write(reinterpret_cast<const char*>(&size), sizeof size);
    data.write(static_cast<const char*>(bytes), std::streamsize(size));
    offset += sizeof size + size;
    return at;
  };
  xml << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\">\n<PolyData>\n";
  if (!field_arrays.empty()) {
    xml << "<FieldData>\n";
    for (const PointArray& a : field_arrays) {
      const std::size_t element = a.vtk_type == "Float32" ? 4 : 8;
      xml << "<DataArray type=\"" << a.vtk_type << "\" Name=\"" << a.name << "\" NumberOfComponents=\"" << a.components
          << "\" NumberOfTuples=\"" << a.bytes.size() / (element * std::size_t(a.components))
          << "\" format=\"appended\" offset=\"" << block(a.bytes.data(), a.bytes.size()) << "\"/>\n";
    }
    xml << "</FieldData>\n";
  }
  xml << "<Piece NumberOfPoints=\""
      << n << "\" NumberOfVerts=\"" << n << "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n<PointData>\n";
  for (const PointArray& a : arrays)
    xml << "<DataArray type=\"" << a.vtk_type << "\" Name=\"" << a.name << "\" NumberOfComponents=\"" << a.components
        << "\" format=\"appended\" offset=\"" << block(a.bytes.data(), a.bytes.size()) << "\"/>\n";
  xml << "</PointData>\n<Points>\n<DataArray type=\"" << PointArray::vtk_type_of<S>()
      << "\" Name=\"Points\" NumberOfComponents=\"3\" format=\"appended\" offset=\""
      << block(points.data(), points.size() * sizeof(S)) << "\"/>\n</Points>\n<Verts>\n";
  xml << "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"appended\" offset=\""
      << block(connectivity.data(), n * 8) << "\"/>\n";
  xml << "<DataArray type=\"Int64\" Name=\"offsets\" format=\"appended\" offset=\"" << block(offsets.data(), n * 8)
      << "\"/>\n</Verts>\n</Piece>\n</PolyData>\n<AppendedData encoding=\"raw\">\n_";
  std::string content = xml.str() + data.str() + "\n</AppendedData>\n</VTKFile>\n";
  write_file_atomically(path, content);
}

// The parallel PolyData file (.pvtp) that joins pieces written by write_vtp (one per rank) into
// one data set for ParaView: `arrays` names the point arrays of the pieces (their values are
// not read here, only name, type and components), `points_type` the points' VTK type, `pieces`
// the piece files relative to the .pvtp.
inline void write_pvtp(const std::filesystem::path& path, const std::string& points_type,
                       const std::vector<PointArray>& arrays, const std::vector<std::string>& pieces) {
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PPolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\">\n<PPolyData GhostLevel=\"0\">\n<PPointData>\n";
  for (const PointArray& a : arrays)
    xml << "<PDataArray type=\"" << a.vtk_type << "\" Name=\"" << a.name << "\" NumberOfComponents=\"" << a.components
        << "\"/>\n";
  xml << "</PPointData>\n<PPoints>\n<PDataArray type=\"" << points_type
      << "\" Name=\"Points\" NumberOfComponents=\"3\"/>\n</PPoints>\n";
  for (const std::string& piece : pieces) xml << "<Piece Source=\"" << piece << "\"/>\n";
  xml << "</PPolyData>\n</VTKFile>\n";
  write_file_atomically(path, xml.str());
}

struct CollectionEntry {
  double time;
  int part;
  std::string file;  // relative to the .pvd
};

inline void write_pvd(const std::filesystem::path& path, const std::vector<CollectionEntry>& entries) {
  std::ostringstream xml;
  xml.precision(17);
  xml << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n<Collection>\n";
  for (const CollectionEntry& e : entries)
    xml << "<DataSet timestep=\"" << e.time << "\" group=\"\" part=\"" << e.part << "\" file=\"" << e.file << "\"/>\n";
  xml << "</Collection>\n</VTKFile>\n";
  write_file_atomically(path, xml.str());
}

}  // namespace unisph::io
