// STL parsing (host only, compiled by the C++ compiler).
#include "unisph/geometry/stl_reader.hpp"

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string_view>

namespace unisph {

namespace {

constexpr std::size_t binary_header_bytes = 84;  // 80-byte header + 32-bit facet count
constexpr std::size_t binary_facet_bytes = 50;   // normal, 3 corners (12 floats) + 16-bit attribute

[[noreturn]] void fail(const std::string& source, const std::string& what) { throw GeometryError(source + ": " + what); }

// Printable ASCII, whitespace, and bytes >= 128 (UTF-8 in solid names); binary floats hold
// control bytes (zeros above all) in practice.
bool is_text_byte(unsigned char c) {
  return c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v' || (c >= 32 && c != 127);
}

bool all_text(std::span<const unsigned char> bytes) {
  for (unsigned char c : bytes)
    if (!is_text_byte(c)) return false;
  return true;
}

bool begins_with_solid(std::span<const unsigned char> bytes) {
  std::size_t i = 0;
  while (i < bytes.size() && (bytes[i] == ' ' || bytes[i] == '\t' || bytes[i] == '\r' || bytes[i] == '\n')) ++i;
  static constexpr char word[] = "solid";
  if (bytes.size() - i < 5) return false;
  for (std::size_t k = 0; k < 5; ++k)
    if (std::tolower(bytes[i + k]) != word[k]) return false;
  return i + 5 == bytes.size() || !std::isalnum(bytes[i + 5]);
}

std::uint32_t little_endian_u32(const unsigned char* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
}
float little_endian_f32(const unsigned char* p) {
  const std::uint32_t bits = little_endian_u32(p);
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

StlFacets parse_binary(std::span<const unsigned char> bytes, std::uint32_t count, const std::string& source) {
  StlFacets result;
  result.binary = true;
  result.solids = 1;
  result.facets.reserve(count);
  for (std::uint32_t f = 0; f < count; ++f) {
    const unsigned char* facet = bytes.data() + binary_header_bytes + std::size_t(f) * binary_facet_bytes;
    RawTriangle t;
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) {
        const float x = little_endian_f32(facet + 12 + 12 * c + 4 * k);  // skip the stored normal
        if (!std::isfinite(x))
          fail(source, "binary STL facet " + std::to_string(f) + " has a non-finite coordinate (corner " +
                           std::to_string(c) + ")");
        t.corner[c][k] = x;
      }
    result.facets.push_back(t);
  }
  return result;
}

// Tokens of an ASCII STL, whitespace-separated, with the line each starts on.
class AsciiTokens {
 public:
  AsciiTokens(std::span<const unsigned char> bytes, const std::string& source)
      : text_(reinterpret_cast<const char*>(bytes.data()), bytes.size()), source_(source) {}

  bool at_end() {
    skip_space();
    return pos_ == text_.size();
  }
  std::size_t line() const { return line_; }

  std::string_view next(const char* expecting) {
    skip_space();
    if (pos_ == text_.size()) fail(source_, "ASCII STL ends early (line " + std::to_string(line_) + "), expected " + expecting);
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    return text_.substr(start, pos_ - start);
  }
  // The rest of the current line (a solid's name), without its line end.
  std::string_view rest_of_line() {
    const std::size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    std::string_view rest = text_.substr(start, pos_ - start);
    while (!rest.empty() && is_space(rest.back())) rest.remove_suffix(1);
    while (!rest.empty() && is_space(rest.front())) rest.remove_prefix(1);
    return rest;
  }
  void expect(std::string_view keyword) {
    const std::size_t line = line_after_space();
    const std::string_view word = next(std::string(keyword).c_str());
    if (!equal_ignoring_case(word, keyword)) {
      if (pos_ == text_.size())
        fail(source_, "ASCII STL ends early (line " + std::to_string(line) + "): its last word '" + printable(word) +
                          "' stands where '" + std::string(keyword) + "' was expected; the file may be truncated");
      fail(source_, "ASCII STL line " + std::to_string(line) + ": expected '" + std::string(keyword) + "', found '" +
                        printable(word) + "'");
    }
  }
  // A number; non-finite values are refused unless `finite_only` is false (stored normals, which
  // exporters write as nan for degenerate facets and which are ignored anyway).
  double number(const char* what, bool finite_only = true) {
    const std::size_t line = line_after_space();
    const std::string_view word = next(what);
    double value = 0;
    std::string_view digits = word;
    if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);  // from_chars does not take a leading '+'
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (error == std::errc::result_out_of_range)
      fail(source_, "ASCII STL line " + std::to_string(line) + ": " + what + " '" + printable(word) +
                        "' is out of the range of double");
    if (error != std::errc() || end != digits.data() + digits.size())
      fail(source_, "ASCII STL line " + std::to_string(line) + ": expected a number (" + what + "), found '" +
                        printable(word) + "'");
    if (finite_only && !std::isfinite(value))
      fail(source_, "ASCII STL line " + std::to_string(line) + ": non-finite " + what + " '" + printable(word) + "'");
    return value;
  }
  static bool equal_ignoring_case(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
    return true;
  }
  // A token shortened for a one-line message.
  static std::string printable(std::string_view word) {
    std::string s(word.substr(0, 40));
    if (word.size() > 40) s += "...";
    return s;
  }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }
  void skip_space() {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }
  std::size_t line_after_space() {
    skip_space();
    return line_;
  }

  std::string_view text_;
  const std::string& source_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
};

StlFacets parse_ascii(std::span<const unsigned char> bytes, const std::string& source) {
  StlFacets result;
  AsciiTokens tokens(bytes, source);
  while (!tokens.at_end()) {
    tokens.expect("solid");
    const std::string solid_name(tokens.rest_of_line());
    const std::size_t solid_line = tokens.line();
    ++result.solids;
    for (;;) {
      if (tokens.at_end())
        fail(source, "ASCII STL ends inside solid '" + AsciiTokens::printable(solid_name) + "' (begun on line " +
                         std::to_string(solid_line) + "): 'endsolid' is missing, the file may be truncated");
      const std::size_t line = tokens.line();
      const std::string_view word = tokens.next("'facet' or 'endsolid'");
      if (AsciiTokens::equal_ignoring_case(word, "endsolid")) {
        tokens.rest_of_line();  // the name after endsolid need not match (exporters disagree)
        break;
      }
      if (!AsciiTokens::equal_ignoring_case(word, "facet"))
        fail(source, "ASCII STL line " + std::to_string(line) + ": expected 'facet' or 'endsolid', found '" +
                         AsciiTokens::printable(word) + "'");
      tokens.expect("normal");
      for (int k = 0; k < 3; ++k) tokens.number("normal component", false);  // must be a number; then ignored
      tokens.expect("outer");
      tokens.expect("loop");
      RawTriangle t;
      for (int c = 0; c < 3; ++c) {
        tokens.expect("vertex");
        for (int k = 0; k < 3; ++k) t.corner[c][k] = tokens.number("vertex coordinate");
      }
      tokens.expect("endloop");
      tokens.expect("endfacet");
      result.facets.push_back(t);
    }
  }
  if (result.solids == 0) fail(source, "ASCII STL holds no 'solid' block");
  return result;
}

}  // namespace

StlFacets parse_stl(std::span<const unsigned char> bytes, const std::string& source) {
  // Some exporters end ASCII files with NUL padding or a DOS end-of-file mark (0x1a).
  std::span<const unsigned char> trimmed = bytes;
  while (!trimmed.empty() && (trimmed.back() == 0 || trimmed.back() == 0x1a)) trimmed = trimmed.first(trimmed.size() - 1);
  const bool text = all_text(trimmed);
  const bool solid = begins_with_solid(trimmed);
  // All text after "solid": ASCII. A binary file is never all text in practice: its count and
  // floats hold zero and control bytes.
  if (solid && text) return parse_ascii(trimmed, source);

  if (bytes.size() < binary_header_bytes) {
    if (bytes.empty()) fail(source, "the file is empty (an STL file has at least a header)");
    fail(source, "not an STL file: " + std::to_string(bytes.size()) +
                     " bytes, too short for a binary STL (84 bytes at least) and not ASCII STL text beginning with 'solid'");
  }
  const std::uint32_t count = little_endian_u32(bytes.data() + 80);
  const std::size_t expected = binary_header_bytes + std::size_t(count) * binary_facet_bytes;
  if (bytes.size() == expected) return parse_binary(bytes, count, source);

  if (solid)  // begins like ASCII but holds binary bytes, and the binary count does not fit either
    fail(source, "begins with 'solid' but is not ASCII STL (it holds non-text bytes), and as binary STL its count of " +
                     std::to_string(count) + " facets needs " + std::to_string(expected) + " bytes, not " +
                     std::to_string(bytes.size()));
  if (bytes.size() < expected) {
    // A count far beyond the size, or a tail that is not whole facets, means this is no STL at all.
    if ((bytes.size() - binary_header_bytes) % binary_facet_bytes == 0 || expected - bytes.size() < expected / 2)
      fail(source, "truncated binary STL: the header announces " + std::to_string(count) + " facets (" +
                       std::to_string(expected) + " bytes) but the file has " + std::to_string(bytes.size()) + " bytes");
  } else if ((bytes.size() - binary_header_bytes) % binary_facet_bytes == 0) {
    fail(source, "binary STL facet count disagrees with the size: the header announces " + std::to_string(count) +
                     " facets (" + std::to_string(expected) + " bytes) but the file has " + std::to_string(bytes.size()) +
                     " bytes, room for " + std::to_string((bytes.size() - binary_header_bytes) / binary_facet_bytes));
  }
  fail(source, "not an STL file: not ASCII STL (no leading 'solid' followed by text) and not binary STL (its count of " +
                   std::to_string(count) + " facets needs " + std::to_string(expected) + " bytes, the file has " +
                   std::to_string(bytes.size()) + ")");
}

StlFacets read_stl(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) fail(path, std::string("cannot open the file: ") + std::strerror(errno));
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (file.bad()) fail(path, "reading the file failed");
  return parse_stl(bytes, path);
}

}  // namespace unisph
