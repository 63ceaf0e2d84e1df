#pragma once
// A table of time -> displacement (or angle) read from a CSV file, interpolated by the natural
// cubic spline through its rows, for a TimeLaw in any memory space.
//
// The CSV format (docs/motion.md):
//   # a paddle signal                 lines whose first non-blank character is '#' are comments
//   time,displacement                 an optional header: the first line that is not a comment,
//   0.0, 0.0                          when none of its fields is a number
//   0.05, 0.0012                      then one row per line: two numbers, time first, separated
//   ...                               by a comma (blanks around them are allowed)
// Times must increase strictly; at least two rows. A row that breaks a rule is an Error with
// one line "file:line: what is wrong".
//
// Why a natural cubic spline: a wall's velocity and acceleration enter the wall boundary
// condition, so a paddle signal needs both continuous. The spline passes through every row with
// continuous displacement, velocity and acceleration (linear interpolation would make the
// velocity jump at every row and the acceleration a train of spikes). Its end conditions
// (zero acceleration at the first and last rows) and its overshoot near corners in the data
// are described in docs/motion.md.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "unisph/memory/discrete_variable.hpp"
#include "unisph/memory/space.hpp"
#include "unisph/motion/time_law.hpp"

namespace unisph {

// The rows of a table as read (host), with the line each came from (0 for rows made in code).
struct MotionTableRows {
  std::string source;  // the file name (or what the rows are), for messages
  std::vector<double> time;
  std::vector<double> value;
  std::vector<std::size_t> line;
};

// Parses CSV text; `source` names it in error messages. Throws Error "source:line: what".
MotionTableRows parse_motion_table_csv(std::string_view text, const std::string& source);
// Reads and parses a CSV file. Throws Error "path: cannot open the file" or as above.
MotionTableRows read_motion_table_csv(const std::string& path);

// The spline's knots in a DiscreteVariable (copied to the device on first use there).
class MotionTable {
 public:
  // Reads `path` (read_motion_table_csv).
  explicit MotionTable(const std::string& path);
  // From rows in memory; checks them as the reader does (rows without a line are named by
  // their index: "source: row 3: ...").
  explicit MotionTable(const MotionTableRows& rows);

  // The law in a memory space; the view stays valid while the table lives.
  TimeLaw law(MemorySpace space) { return table_law(knots_.read(space)); }
  template <InMemorySpace P>
  TimeLaw law(P) {
    return law(P::space);
  }

  Index size() const { return knots_.size(); }
  Real start_time() const { return start_; }
  Real end_time() const { return end_; }
  const std::string& source() const { return source_; }

 private:
  void build(const MotionTableRows& rows);

  std::string source_;
  DiscreteVariable<TableKnot> knots_;
  Real start_ = 0, end_ = 0;
};

}  // namespace unisph
