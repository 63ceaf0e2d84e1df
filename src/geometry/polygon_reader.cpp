// Polygon text files (host only).
#include "unisph/geometry/polygon_reader.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "unisph/geometry/winding_number.hpp"

namespace unisph {

namespace {

using Vec2 = Vec<double, 2>;

[[noreturn]] void fail(const std::string& source, std::size_t line, const std::string& what) {
  throw GeometryError(source + ": line " + std::to_string(line) + ": " + what);
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

std::string shortened(std::string_view s) { return s.size() > 40 ? std::string(s.substr(0, 40)) + "..." : std::string(s); }

double signed_area(const std::vector<Vec2>& loop) {
  double twice = 0.0;
  for (std::size_t i = 0; i < loop.size(); ++i) twice += cross(loop[i], loop[(i + 1) % loop.size()]);
  return 0.5 * twice;
}

// Winding number of a closed loop around p (+1 inside a counter-clockwise loop).
double winding(const std::vector<Vec2>& loop, const Vec2& p) {
  double angle = 0.0;
  for (std::size_t i = 0; i < loop.size(); ++i) angle += subtended_angle(p, loop[i], loop[(i + 1) % loop.size()]);
  return angle / (2.0 * pi<double>());
}

}  // namespace

LoadedPolygons parse_polygons(std::string_view text, const std::string& source) {
  std::vector<std::vector<Vec2>> loops;
  std::vector<std::size_t> loop_line;
  LoadedPolygons result;
  PolygonReport& report = result.report;

  auto close_loop = [&](std::size_t line) {
    if (loops.empty()) return;
    std::vector<Vec2>& loop = loops.back();
    if (loop.size() > 1 && loop.back() == loop.front()) {
      loop.pop_back();
      ++report.repeated_vertices_removed;
    }
    if (loop.size() < 3)
      fail(source, loop_line.back(), "loop " + std::to_string(loops.size() - 1) + " has " + std::to_string(loop.size()) +
                                         " distinct vertices; a closed polygon needs at least 3 (it ends on line " +
                                         std::to_string(line) + ")");
    if (signed_area(loop) == 0.0)
      fail(source, loop_line.back(), "loop " + std::to_string(loops.size() - 1) + " has zero area");
  };

  std::size_t line_number = 0;
  std::size_t position = 0;
  while (position <= text.size()) {
    const std::size_t end = std::min(text.find('\n', position), text.size());
    std::string_view line = text.substr(position, end - position);
    position = end + 1;
    ++line_number;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    line = trim(line);
    if (line.empty()) continue;
    if (line == "loop") {
      close_loop(line_number);
      loops.emplace_back();
      loop_line.push_back(line_number);
      continue;
    }
    // Two numbers.
    double xy[2];
    std::string_view rest = line;
    for (int k = 0; k < 2; ++k) {
      rest = trim(rest);
      std::size_t length = 0;
      while (length < rest.size() && !is_space(rest[length])) ++length;
      const std::string_view word = rest.substr(0, length);
      if (word.empty()) fail(source, line_number, "expected two numbers 'x y', found '" + shortened(line) + "'");
      std::string_view digits = word;
      if (digits.front() == '+') digits.remove_prefix(1);
      const auto [stop, error] = std::from_chars(digits.data(), digits.data() + digits.size(), xy[k]);
      if (error != std::errc() || stop != digits.data() + digits.size())
        fail(source, line_number, "expected a number, found '" + shortened(word) + "'");
      if (!std::isfinite(xy[k])) fail(source, line_number, "non-finite coordinate '" + shortened(word) + "'");
      rest = rest.substr(length);
    }
    if (!trim(rest).empty())
      fail(source, line_number, "expected two numbers 'x y', found more: '" + shortened(line) + "'");
    if (loops.empty()) fail(source, line_number, "a vertex before the first 'loop' line");
    const Vec2 vertex{{xy[0], xy[1]}};
    if (!loops.back().empty() && loops.back().back() == vertex) {
      ++report.repeated_vertices_removed;
      continue;
    }
    loops.back().push_back(vertex);
  }
  close_loop(line_number);

  // Orientation by nesting depth: counter-clockwise at even depth, clockwise at odd depth.
  report.loops = loops.size();
  report.depth.assign(loops.size(), 0);
  for (std::size_t a = 0; a < loops.size(); ++a) {
    // Midpoint of the first edge: on the loop, so inside exactly the loops that contain the loop
    // (loops are assumed not to cross each other).
    const Vec2 probe = (loops[a][0] + loops[a][1]) * 0.5;
    for (std::size_t b = 0; b < loops.size(); ++b)
      if (b != a && std::abs(winding(loops[b], probe)) > 0.5) ++report.depth[a];
  }
  PolygonSet& set = result.polygons;
  set.source = source;
  for (std::size_t a = 0; a < loops.size(); ++a) {
    const bool counter_clockwise = signed_area(loops[a]) > 0.0;
    if (counter_clockwise != (report.depth[a] % 2 == 0)) {
      std::reverse(loops[a].begin(), loops[a].end());
      report.loops_turned.push_back(a);
    }
    report.area += signed_area(loops[a]);
    set.vertices.insert(set.vertices.end(), loops[a].begin(), loops[a].end());
    set.loop_start.push_back(std::uint32_t(set.vertices.size()));
  }
  if (!set.vertices.empty()) {
    report.box_min = report.box_max = set.vertices[0];
    for (const Vec2& v : set.vertices) {
      report.box_min = min(report.box_min, v);
      report.box_max = max(report.box_max, v);
    }
  }
  return result;
}

LoadedPolygons read_polygons(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw GeometryError(path + ": cannot open the file: " + std::strerror(errno));
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (text.find('\0') != std::string::npos) throw GeometryError(path + ": not a polygon text file (it holds zero bytes)");
  return parse_polygons(text, path);
}

}  // namespace unisph
