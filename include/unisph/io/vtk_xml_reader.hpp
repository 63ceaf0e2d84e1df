#pragma once
// Reads back the VTK XML PolyData (.vtp) files unisph writes (io/vtk_xml_writer.hpp): the
// points, the named point arrays and the dataset's field arrays, from raw appended data with
// 64-bit block headers, little-endian. Every array is returned as doubles. It is not a general
// VTK reader: other encodings (ascii, base64, compressed) are refused by name. Every problem
// (a missing file, a file that is not such PolyData, truncated blocks, sizes that disagree,
// non-finite values) is a VtkReadError of one line naming the file and what is wrong. Host code.
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "unisph/core/error.hpp"

namespace unisph::io {

static_assert(std::endian::native == std::endian::little,
              "unisph writes and reads VTK appended data as the host's little-endian bytes.");

class VtkReadError : public Error {
 public:
  using Error::Error;
};

struct VtkArray {
  std::string name;
  std::string vtk_type;  // Float32, Float64, UInt64, Int64
  int components = 1;
  std::vector<double> values;  // tuples one after another
};

struct PolyDataFile {
  std::string path;
  std::uint64_t points = 0;
  std::vector<double> coordinates;  // three per point
  std::vector<VtkArray> point_arrays;
  std::vector<VtkArray> field_arrays;

  // One line whatever the file holds: control characters (a newline in an attribute) become
  // blanks, and quoted attribute values are cut to 80 characters (vtk_reader_detail::shown).
  [[noreturn]] void fail(const std::string& what) const {
    std::string line = path + ": " + what;
    for (char& c : line)
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
    throw VtkReadError(line);
  }

  // The point array `name` with `components` components, or a one-line error.
  const VtkArray& point_array(const std::string& name, int components) const {
    return find(point_arrays, name, components, "point array");
  }
  // The field (dataset) array `name` holding one value, as that value.
  double field_value(const std::string& name) const {
    const VtkArray& a = find(field_arrays, name, 1, "field array");
    if (a.values.size() != 1) fail("field array '" + name + "' holds " + std::to_string(a.values.size()) + " values, not 1");
    return a.values[0];
  }

 private:
  const VtkArray& find(const std::vector<VtkArray>& arrays, const std::string& name, int components,
                       const char* kind) const {
    for (const VtkArray& a : arrays)
      if (a.name == name) {
        if (a.components != components)
          fail(std::string(kind) + " '" + name + "' has " + std::to_string(a.components) + " components, not " +
               std::to_string(components));
        return a;
      }
    fail(std::string("has no ") + kind + " '" + name + "'");
  }
};

namespace vtk_reader_detail {

// An attribute value as quoted in a message: at most 80 characters.
inline std::string shown(const std::string& value) {
  return value.size() <= 80 ? value : value.substr(0, 80) + "...";
}

// One XML tag of the header: its name ("DataArray", "/PointData", ...) and attributes.
struct Tag {
  std::string name;
  std::map<std::string, std::string> attributes;
};

inline std::vector<Tag> tags(const std::string& header, const PolyDataFile& file) {
  std::vector<Tag> out;
  std::size_t at = 0;
  while ((at = header.find('<', at)) != std::string::npos) {
    const std::size_t end = header.find('>', at);
    if (end == std::string::npos) file.fail("its XML header ends inside a tag");
    std::string body = header.substr(at + 1, end - at - 1);
    at = end + 1;
    if (body.empty() || body[0] == '?' || body[0] == '!') continue;
    if (body.back() == '/') body.pop_back();
    Tag tag;
    std::size_t k = 0;
    while (k < body.size() && !std::isspace(static_cast<unsigned char>(body[k]))) tag.name += body[k++];
    while (k < body.size()) {
      while (k < body.size() && std::isspace(static_cast<unsigned char>(body[k]))) ++k;
      if (k >= body.size()) break;
      const std::size_t eq = body.find('=', k);
      if (eq == std::string::npos || eq + 1 >= body.size() || body[eq + 1] != '"')
        file.fail("its XML tag <" + shown(tag.name) + "> has a malformed attribute");
      const std::size_t close = body.find('"', eq + 2);
      if (close == std::string::npos) file.fail("its XML tag <" + shown(tag.name) + "> has an unterminated attribute");
      tag.attributes[body.substr(k, eq - k)] = body.substr(eq + 2, close - eq - 2);
      k = close + 1;
    }
    out.push_back(std::move(tag));
  }
  return out;
}

inline std::uint64_t unsigned_attribute(const Tag& tag, const std::string& key, const PolyDataFile& file) {
  const auto it = tag.attributes.find(key);
  if (it == tag.attributes.end()) file.fail("<" + shown(tag.name) + "> has no " + key + " attribute");
  const std::string& text = it->second;
  if (text.empty() || text.size() > 19 || text.find_first_not_of("0123456789") != std::string::npos)
    file.fail("<" + shown(tag.name) + "> " + key + " = \"" + shown(text) + "\" is not a non-negative integer");
  return std::stoull(text);
}

inline int type_size(const std::string& type) {
  if (type == "Float32") return 4;
  if (type == "Float64" || type == "UInt64" || type == "Int64") return 8;
  return 0;
}

template <class S>
double load(const unsigned char* at) {
  S value;
  std::memcpy(&value, at, sizeof value);
  return double(value);
}

}  // namespace vtk_reader_detail

// Parses the bytes of a .vtp file; `name` names it in messages (fuzz/vtp_fuzzer.cpp calls this).
inline PolyDataFile parse_vtp(const std::string& content, const std::string& name) {
  namespace d = vtk_reader_detail;
  PolyDataFile file;
  file.path = name;
  if (content.rfind("<?xml", 0) != 0 && content.rfind("<VTKFile", 0) != 0)
    file.fail("is not a VTK XML file (it does not start with \"<?xml\" or \"<VTKFile\")");
  const std::size_t appended = content.find("<AppendedData");
  const std::string header = content.substr(0, appended);
  const std::vector<d::Tag> tags = d::tags(header, file);

  const d::Tag* vtk_file = nullptr;
  for (const d::Tag& t : tags)
    if (t.name == "VTKFile") vtk_file = &t;
  if (!vtk_file) file.fail("is not a VTK XML file (no <VTKFile> element)");
  const auto attribute = [&](const d::Tag& t, const std::string& key) {
    const auto it = t.attributes.find(key);
    return it == t.attributes.end() ? std::string() : it->second;
  };
  if (attribute(*vtk_file, "type") != "PolyData")
    file.fail("is a VTK '" + d::shown(attribute(*vtk_file, "type")) + "' file, not PolyData (.vtp)");
  if (attribute(*vtk_file, "byte_order") != "LittleEndian")
    file.fail("has byte_order \"" + d::shown(attribute(*vtk_file, "byte_order")) + "\"; this reader reads LittleEndian");
  if (attribute(*vtk_file, "header_type") != "UInt64")
    file.fail("has header_type \"" + d::shown(attribute(*vtk_file, "header_type")) + "\"; this reader reads the UInt64 block "
              "headers unisph writes");
  if (attribute(*vtk_file, "compressor") != "") file.fail("is compressed; this reader reads uncompressed data");

  // The arrays in the header, each with where it belongs and how many tuples it must hold.
  struct Pending {
    VtkArray array;
    std::uint64_t tuples = 0;
    std::uint64_t offset = 0;
    enum class Where { point, field, points, other } where;
  };
  std::vector<Pending> pending;
  std::string section;
  int pieces = 0;
  for (const d::Tag& t : tags) {
    if (t.name == "Piece") {
      if (++pieces > 1) file.fail("has more than one <Piece>; unisph writes one");
      file.points = d::unsigned_attribute(t, "NumberOfPoints", file);
    } else if (t.name == "PointData" || t.name == "FieldData" || t.name == "Points" || t.name == "Verts" ||
               t.name == "Lines" || t.name == "Strips" || t.name == "Polys" || t.name == "CellData") {
      section = t.name;
    } else if (!t.name.empty() && t.name[0] == '/') {
      if (t.name.substr(1) == section) section.clear();
    } else if (t.name == "DataArray") {
      Pending p;
      p.array.name = attribute(t, "Name");
      p.array.vtk_type = attribute(t, "type");
      const std::string what = "array '" + d::shown(p.array.name) + "' (in <" + section + ">)";
      if (d::type_size(p.array.vtk_type) == 0)
        file.fail(what + " has type \"" + d::shown(p.array.vtk_type) + "\"; this reader reads Float32, Float64, UInt64 and Int64");
      if (attribute(t, "format") != "appended")
        file.fail(what + " has format \"" + d::shown(attribute(t, "format")) + "\"; this reader reads the raw appended data "
                  "unisph writes");
      p.offset = d::unsigned_attribute(t, "offset", file);
      const std::string components = attribute(t, "NumberOfComponents");
      p.array.components = components.empty() ? 1 : int(d::unsigned_attribute(t, "NumberOfComponents", file));
      if (p.array.components < 1 || p.array.components > 9)
        file.fail(what + " has " + d::shown(components) + " components (1 to 9 expected)");
      if (section == "PointData") p.where = Pending::Where::point;
      else if (section == "Points") p.where = Pending::Where::points;
      else if (section == "FieldData") {
        p.where = Pending::Where::field;
        p.tuples = d::unsigned_attribute(t, "NumberOfTuples", file);
      } else p.where = Pending::Where::other;
      pending.push_back(std::move(p));
    }
  }
  if (pieces == 0) file.fail("has no <Piece>");

  if (appended == std::string::npos) file.fail("has no <AppendedData> (truncated, or not written by unisph)");
  const std::size_t tag_end = content.find('>', appended);
  if (tag_end == std::string::npos) file.fail("is truncated inside <AppendedData>");
  if (content.substr(appended, tag_end - appended).find("encoding=\"raw\"") == std::string::npos)
    file.fail("has appended data that is not raw (base64 is not read)");
  const std::size_t underscore = content.find('_', tag_end);
  if (underscore == std::string::npos) file.fail("is truncated: its appended data has no '_' start marker");
  const std::size_t data = underscore + 1;
  const std::uint64_t available = content.size() - data;
  const auto* bytes = reinterpret_cast<const unsigned char*>(content.data()) + data;

  bool have_points = false;
  for (Pending& p : pending) {
    if (p.where == Pending::Where::point || p.where == Pending::Where::points) p.tuples = file.points;
    const std::string what = p.where == Pending::Where::points ? std::string("the points")
                                                                : "array '" + d::shown(p.array.name) + "'";
    const std::uint64_t size = d::type_size(p.array.vtk_type);
    if (p.where == Pending::Where::points && p.array.components != 3)
      file.fail("the points have " + std::to_string(p.array.components) + " components, not 3");
    if (p.offset > available || available - p.offset < 8)
      file.fail("is truncated: " + what + " starts at byte " + std::to_string(p.offset) + " of " +
                std::to_string(available) + " bytes of appended data");
    std::uint64_t block = 0;
    std::memcpy(&block, bytes + p.offset, 8);
    if (p.where == Pending::Where::other) continue;  // connectivity and offsets: nothing to keep
    if (p.tuples > (std::uint64_t(1) << 40)) file.fail(what + " claims " + std::to_string(p.tuples) + " tuples");
    const std::uint64_t expected = p.tuples * std::uint64_t(p.array.components) * size;
    if (block != expected)
      file.fail(what + " holds " + std::to_string(block) + " bytes where " + std::to_string(p.tuples) + " tuples of " +
                std::to_string(p.array.components) + " " + p.array.vtk_type + " take " + std::to_string(expected));
    if (available - p.offset - 8 < block)
      file.fail("is truncated: " + what + " needs " + std::to_string(block) + " bytes, " +
                std::to_string(available - p.offset - 8) + " are left");
    const unsigned char* at = bytes + p.offset + 8;
    const std::uint64_t count = p.tuples * std::uint64_t(p.array.components);
    p.array.values.resize(count);
    for (std::uint64_t k = 0; k < count; ++k) {
      const unsigned char* v = at + k * size;
      double value = 0;
      if (p.array.vtk_type == "Float32") value = d::load<float>(v);
      else if (p.array.vtk_type == "Float64") value = d::load<double>(v);
      else if (p.array.vtk_type == "UInt64") value = d::load<std::uint64_t>(v);
      else value = d::load<std::int64_t>(v);
      if (!std::isfinite(value)) {
        std::ostringstream s;
        s << what << ": the value of tuple " << k / std::uint64_t(p.array.components) << " (component "
          << k % std::uint64_t(p.array.components) << ") is not finite (" << value << ")";
        file.fail(s.str());
      }
      p.array.values[k] = value;
    }
    if (p.where == Pending::Where::points) {
      if (have_points) file.fail("has more than one points array");
      have_points = true;
      file.coordinates = std::move(p.array.values);
    } else {
      std::vector<VtkArray>& list = p.where == Pending::Where::point ? file.point_arrays : file.field_arrays;
      for (const VtkArray& a : list)
        if (a.name == p.array.name) file.fail("has two arrays named '" + d::shown(a.name) + "'");
      list.push_back(std::move(p.array));
    }
  }
  if (!have_points) file.fail("has no <Points> array");
  return file;
}

inline PolyDataFile read_vtp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw VtkReadError(path.string() + ": cannot open the file");
  const std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw VtkReadError(path.string() + ": reading the file failed");
  return parse_vtp(content, path.string());
}

}  // namespace unisph::io
