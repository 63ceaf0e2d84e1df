// Motion tables: CSV parsing and the natural cubic spline's second derivatives (host only).
#include "unisph/motion/motion_table.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>

#include "unisph/core/error.hpp"

namespace unisph {

namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

std::string shortened(std::string_view s) { return s.size() > 40 ? std::string(s.substr(0, 40)) + "..." : std::string(s); }

// The shortest text that reads back as v.
std::string number_text(double v) {
  char buffer[64];
  const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, v);
  return error == std::errc() ? std::string(buffer, end) : std::string("?");
}

// Where a row is, for a message: "source:line" or "source: row i" (1-based).
std::string where(const MotionTableRows& rows, std::size_t i) {
  if (i < rows.line.size() && rows.line[i] != 0) return rows.source + ":" + std::to_string(rows.line[i]);
  return rows.source + ": row " + std::to_string(i + 1);
}

// A whole field as a number: optional blanks and a leading '+', nothing after the digits.
bool parse_number(std::string_view field, double& value) {
  std::string_view digits = trim(field);
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
  if (digits.empty()) return false;
  const auto [stop, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  return error == std::errc() && stop == digits.data() + digits.size();
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = line.find(',', begin);
    fields.push_back(trim(line.substr(begin, comma == std::string_view::npos ? std::string_view::npos : comma - begin)));
    if (comma == std::string_view::npos) break;
    begin = comma + 1;
  }
  return fields;
}

// The rules every table meets: as many values as times, finite numbers, times strictly
// increasing, at least two rows.
void check_rows(const MotionTableRows& rows) {
  if (rows.value.size() != rows.time.size())
    throw Error(rows.source + ": " + std::to_string(rows.time.size()) + " times but " +
                std::to_string(rows.value.size()) + " values");
  for (std::size_t i = 0; i < rows.time.size(); ++i) {
    if (!std::isfinite(rows.time[i])) throw Error(where(rows, i) + ": the time is not finite");
    if (!std::isfinite(rows.value[i])) throw Error(where(rows, i) + ": the displacement is not finite");
    if (i > 0 && !(rows.time[i] > rows.time[i - 1])) {
      const std::string previous = i - 1 < rows.line.size() && rows.line[i - 1] != 0
                                       ? "line " + std::to_string(rows.line[i - 1])
                                       : "row " + std::to_string(i);
      throw Error(where(rows, i) + ": time " + number_text(rows.time[i]) + " is not after " +
                  number_text(rows.time[i - 1]) + " on " + previous + " (times must increase strictly)");
    }
  }
  if (rows.time.empty())
    throw Error(rows.source + ": no rows; a motion table needs at least 2 rows of time, displacement");
  if (rows.time.size() < 2)
    throw Error(where(rows, 0) + ": the only row; a motion table needs at least 2 rows of time, displacement");
}

}  // namespace

MotionTableRows parse_motion_table_csv(std::string_view text, const std::string& source) {
  MotionTableRows rows;
  rows.source = source;
  bool header_possible = true;
  std::size_t line_number = 0, position = 0;
  while (position < text.size()) {
    const std::size_t end = std::min(text.find('\n', position), text.size());
    const std::string_view line = trim(text.substr(position, end - position));
    position = end + 1;
    ++line_number;
    if (line.empty() || line.front() == '#') continue;
    const std::vector<std::string_view> fields = split_fields(line);
    const std::string location = source + ":" + std::to_string(line_number);
    if (header_possible) {
      header_possible = false;
      bool any_number = false;
      double ignored = 0;
      for (std::string_view f : fields) any_number = any_number || parse_number(f, ignored);
      if (!any_number) continue;  // the header
    }
    if (fields.size() != 2)
      throw Error(location + ": expected 2 fields (time, displacement) separated by a comma, found " +
                  std::to_string(fields.size()) + ": '" + shortened(line) + "'");
    double t = 0, q = 0;
    if (!parse_number(fields[0], t)) throw Error(location + ": expected a number (time), found '" + shortened(fields[0]) + "'");
    if (!parse_number(fields[1], q))
      throw Error(location + ": expected a number (displacement), found '" + shortened(fields[1]) + "'");
    if (!std::isfinite(t)) throw Error(location + ": the time '" + shortened(fields[0]) + "' is not finite");
    if (!std::isfinite(q)) throw Error(location + ": the displacement '" + shortened(fields[1]) + "' is not finite");
    rows.time.push_back(t);
    rows.value.push_back(q);
    rows.line.push_back(line_number);
  }
  check_rows(rows);
  return rows;
}

MotionTableRows read_motion_table_csv(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw Error(path + ": cannot open the file");
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) throw Error(path + ": cannot read the file");
  return parse_motion_table_csv(text.str(), path);
}

MotionTable::MotionTable(const std::string& path) : knots_("MotionTableKnots") { build(read_motion_table_csv(path)); }

MotionTable::MotionTable(const MotionTableRows& rows) : knots_("MotionTableKnots") { build(rows); }

void MotionTable::build(const MotionTableRows& rows) {
  check_rows(rows);
  source_ = rows.source;
  const std::size_t n = rows.time.size();
  const std::vector<double>& t = rows.time;
  const std::vector<double>& q = rows.value;
  // Second derivatives m of the natural spline (m_0 = m_n-1 = 0): for 0 < i < n-1,
  //   h_i-1 m_i-1 + 2 (h_i-1 + h_i) m_i + h_i m_i+1 = 6 (d_i - d_i-1),  d_i = (q_i+1 - q_i) / h_i,
  // a diagonally dominant tridiagonal system, solved by elimination without pivoting.
  std::vector<double> m(n, 0.0);
  if (n > 2) {
    std::vector<double> diagonal(n, 0.0), right(n, 0.0);
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const double h0 = t[i] - t[i - 1], h1 = t[i + 1] - t[i];
      diagonal[i] = 2.0 * (h0 + h1);
      right[i] = 6.0 * ((q[i + 1] - q[i]) / h1 - (q[i] - q[i - 1]) / h0);
    }
    for (std::size_t i = 2; i + 1 < n; ++i) {  // forward elimination of the sub-diagonal h_i-1
      const double factor = (t[i] - t[i - 1]) / diagonal[i - 1];
      diagonal[i] -= factor * (t[i] - t[i - 1]);
      right[i] -= factor * right[i - 1];
    }
    for (std::size_t i = n - 2; i >= 1; --i) {  // back substitution (super-diagonal h_i)
      m[i] = (right[i] - (t[i + 1] - t[i]) * m[i + 1]) / diagonal[i];
    }
  }
  knots_.resize(n);
  View<TableKnot> host = knots_.write(MemorySpace::host);
  for (std::size_t i = 0; i < n; ++i) {
    host[i] = {Real(t[i]), Real(q[i]), Real(m[i])};
    if (i > 0 && !(host[i].time > host[i - 1].time))  // only where Real is float
      throw Error(where(rows, i) + ": time " + number_text(t[i]) + " is not after " + number_text(t[i - 1]) +
                  " in the precision of unisph::Real");
  }
  start_ = Real(t.front());
  end_ = Real(t.back());
}

}  // namespace unisph
