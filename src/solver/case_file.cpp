// Case-file reader: TOML through toml++ (header-only, Debian's libtomlplusplus-dev). Every
// key is checked against the schema below, so a misspelt key is an error rather than a
// silently ignored setting.
#include "unisph/solver/case_file.hpp"

#include "unisph/solver/tank_particles.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#define TOML_EXCEPTIONS 1
#define TOML_HEADER_ONLY 1  // Debian ships toml++ as a shared library too; header-only keeps it out of the link of unisph users
// toml++ 3.x checks its parser's internal state with TOML_ASSERT_ASSUME: an assert in debug
// builds, an optimiser assumption under clang in release builds. Malformed input can break
// those expectations before toml++ reaches its own error report (the fuzzer found several), so
// they are switched off here: the parser then reports the error, as it does in GCC release builds.
#include <toml++/impl/preprocessor.h>
#undef TOML_ASSERT_ASSUME
#define TOML_ASSERT_ASSUME(expr) static_assert(true)
#include <toml++/toml.h>

namespace unisph::sph {
namespace {

// A message that quotes the file's own text stays one line: control characters (a multi-line
// string value, a quoted key with "\n" in it) are written as escapes.
std::string one_line(const std::string& text) {
  static const char hex[] = "0123456789abcdef";
  std::string out;
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c == '\n')
      out += "\\n";
    else if (c == '\r')
      out += "\\r";
    else if (c == '\t')
      out += "\\t";
    else if (c < 0x20 || c == 0x7f)
      out += std::string("\\x") + hex[c >> 4] + hex[c & 15];
    else
      out += ch;
  }
  return out;
}

struct Reader {
  const std::string& source;

  [[noreturn]] void fail(const toml::node* node, const std::string& key, const std::string& what) const {
    std::string line = "?";
    if (node && node->source().begin.line > 0) line = std::to_string(node->source().begin.line);
    throw CaseFileError(one_line(source + ":" + line + ": key '" + key + "': " + what));
  }
  [[noreturn]] void fail_at(const toml::table& table, const std::string& key, const std::string& what) const {
    fail(&table, key, what);
  }

  const toml::table& table(const toml::table& root, const std::string& name, bool required) const {
    static const toml::table empty;
    const toml::node* node = root.get(name);
    if (!node) {
      if (required) fail_at(root, name, "missing table [" + name + "]");
      return empty;
    }
    if (!node->is_table()) fail(node, name, "must be a table");
    return *node->as_table();
  }

  void only_keys(const toml::table& table, const std::string& prefix, std::initializer_list<std::string_view> known) const {
    only_keys(table, prefix, std::vector<std::string_view>(known));
  }
  void only_keys(const toml::table& table, const std::string& prefix, const std::vector<std::string_view>& known) const {
    for (const auto& [key, node] : table) {
      bool ok = false;
      for (auto k : known) ok = ok || key.str() == k;
      if (!ok) {
        std::string list;
        for (auto k : known) list += (list.empty() ? "" : ", ") + std::string(k);
        fail(&node, prefix + std::string(key.str()), "unknown key (known here: " + list + ")");
      }
    }
  }

  double number(const toml::table& table, const std::string& prefix, const std::string& key, const double* fallback) const {
    const toml::node* node = table.get(key);
    if (!node) {
      if (fallback) return *fallback;
      fail_at(table, prefix + key, "missing value");
    }
    double value = 0;
    if (auto i = node->as_integer())
      value = double(i->get());
    else if (auto f = node->as_floating_point())
      value = f->get();
    else
      fail(node, prefix + key, std::string("must be a number (it is a ") + type_name(*node) + ")");
    if (!std::isfinite(value)) fail(node, prefix + key, "must be finite");
    return value;
  }
  double positive(const toml::table& table, const std::string& prefix, const std::string& key,
                  const double* fallback = nullptr) const {
    const double v = number(table, prefix, key, fallback);
    if (!(v > 0)) fail(table.get(key) ? table.get(key) : &table, prefix + key, "must be positive (it is " + format(v) + ")");
    return v;
  }
  double non_negative(const toml::table& table, const std::string& prefix, const std::string& key, double fallback) const {
    const double v = number(table, prefix, key, &fallback);
    if (v < 0) fail(table.get(key), prefix + key, "must not be negative (it is " + format(v) + ")");
    return v;
  }
  bool boolean(const toml::table& table, const std::string& prefix, const std::string& key, bool fallback) const {
    const toml::node* node = table.get(key);
    if (!node) return fallback;
    if (!node->is_boolean())
      fail(node, prefix + key, std::string("must be true or false (it is a ") + type_name(*node) + ")");
    return node->as_boolean()->get();
  }
  std::string text(const toml::table& table, const std::string& prefix, const std::string& key, const std::string* fallback) const {
    const toml::node* node = table.get(key);
    if (!node) {
      if (fallback) return *fallback;
      fail_at(table, prefix + key, "missing value");
    }
    if (auto s = node->as_string()) return s->get();
    fail(node, prefix + key, std::string("must be a string (it is a ") + type_name(*node) + ")");
  }
  // One of a few words; the first is the default where the key is absent.
  std::string choice(const toml::table& table, const std::string& prefix, const std::string& key,
                     std::initializer_list<std::string_view> words) const {
    const std::string fallback(*words.begin());
    std::string value = text(table, prefix, key, &fallback);
    std::string list;  // "a", "b" or "c"
    std::size_t k = 0;
    for (auto w : words) {
      if (value == w) return value;
      if (k > 0) list += k + 1 == words.size() ? " or " : ", ";
      list.append("\"").append(w).append("\"");
      ++k;
    }
    fail(table.get(key), prefix + key, "must be " + list + " (it is \"" + value + "\")");
  }
  long long integer(const toml::table& table, const std::string& prefix, const std::string& key, const long long* fallback) const {
    const toml::node* node = table.get(key);
    if (!node) {
      if (fallback) return *fallback;
      fail_at(table, prefix + key, "missing value");
    }
    if (auto i = node->as_integer()) return i->get();
    fail(node, prefix + key, std::string("must be an integer (it is a ") + type_name(*node) + ")");
  }
  std::vector<double> vector(const toml::table& table, const std::string& prefix, const std::string& key, int size,
                             bool positive_entries) const {
    const toml::node* node = table.get(key);
    if (!node) fail_at(table, prefix + key, "missing value");
    const toml::array* array = node->as_array();
    if (!array) fail(node, prefix + key, std::string("must be an array of ") + std::to_string(size) + " numbers (it is a " + type_name(*node) + ")");
    if (int(array->size()) != size)
      fail(node, prefix + key, "must have " + std::to_string(size) + " entries, one per axis (it has " + std::to_string(array->size()) + ")");
    std::vector<double> out;
    for (const toml::node& e : *array) {
      double v = 0;
      if (auto i = e.as_integer())
        v = double(i->get());
      else if (auto f = e.as_floating_point())
        v = f->get();
      else
        fail(node, prefix + key, std::string("entries must be numbers (one is a ") + type_name(e) + ")");
      if (!std::isfinite(v)) fail(node, prefix + key, "entries must be finite");
      if (positive_entries && !(v > 0)) fail(node, prefix + key, "entries must be positive (one is " + format(v) + ")");
      out.push_back(v);
    }
    return out;
  }

  static const char* type_name(const toml::node& node) {
    switch (node.type()) {
      case toml::node_type::string: return "string";
      case toml::node_type::integer: return "integer";
      case toml::node_type::floating_point: return "floating-point number";
      case toml::node_type::boolean: return "boolean";
      case toml::node_type::array: return "array";
      case toml::node_type::table: return "table";
      default: return "date or time";
    }
  }
  static std::string format(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }
};

// toml++ 3.x asserts (assumes, in release builds with clang) that a table header's first
// non-blank character after '[' starts a key; a header such as "[ (x)]" breaks that promise
// (found by fuzz/case_fuzzer.cpp). Such a line is refused here before toml++ sees it. A line
// starting with '[' can otherwise only be an array inside an array, which no case key takes.
void refuse_headers_without_key(std::string_view text, const std::string& source) {
  std::size_t line = 1;
  for (std::size_t at = 0; at < text.size(); ++line) {
    std::size_t end = text.find('\n', at);
    if (end == std::string_view::npos) end = text.size();
    std::size_t k = at;
    while (k < end && (text[k] == ' ' || text[k] == '\t')) ++k;
    if (k < end && text[k] == '[') {
      ++k;
      if (k < end && text[k] == '[') ++k;
      while (k < end && (text[k] == ' ' || text[k] == '\t')) ++k;
      const unsigned char c = k < end ? static_cast<unsigned char>(text[k]) : '\n';
      const bool key_start = std::isalnum(c) || c == '_' || c == '-' || c == '"' || c == '\'';
      if (!key_start)
        throw CaseFileError(source + ":" + std::to_string(line) + ": not valid TOML: a table header must start with a key name");
    }
    at = end + 1;
  }
}

// toml++ 3.x reaches an unreachable point (undefined behaviour) on some invalid UTF-8 (found by
// the fuzzer: a 0xE5 lead byte followed by ']'), so the text is checked to be UTF-8 first.
void refuse_invalid_utf8(std::string_view text, const std::string& source) {
  std::size_t line = 1;
  for (std::size_t k = 0; k < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[k]);
    if (c == '\n') ++line;
    int length = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    bool valid = length > 0 && k + std::size_t(length) <= text.size();
    std::uint32_t code = length == 1 ? c : length == 2 ? (c & 0x1Fu) : length == 3 ? (c & 0x0Fu) : (c & 0x07u);
    for (int b = 1; valid && b < length; ++b) {
      const unsigned char t = static_cast<unsigned char>(text[k + b]);
      valid = (t >> 6) == 0x2;
      code = (code << 6) | (t & 0x3Fu);
    }
    if (valid && length > 1) {
      const std::uint32_t smallest[5] = {0, 0, 0x80, 0x800, 0x10000};
      valid = code >= smallest[length] && code <= 0x10FFFF && !(code >= 0xD800 && code <= 0xDFFF);
    }
    if (!valid) throw CaseFileError(source + ":" + std::to_string(line) + ": not valid TOML: the text is not valid UTF-8");
    k += std::size_t(length);
  }
}

// TOML allows non-ASCII characters only in strings and comments; toml++ 3.x reaches an
// unreachable point (undefined behaviour) when a valid non-ASCII letter (U+023E, found by the
// fuzzer) appears where it classifies bare-key characters, and when one follows a line-ending
// backslash in a multi-line string (U+FEDF), and in a string holding control characters. So the
// text must be ASCII outside comments (every case value is an ASCII word or number). Inside
// comments, too, toml++ 3.x goes wrong on some characters (U+FEEF after a malformed date, found by
// the fuzzer: its non-ASCII whitespace test reaches an unreachable point), so the text it is given
// has each non-ASCII byte of a comment replaced by '?': comments carry no value, and lines and
// columns stay where they were.
std::string ascii_for_toml(std::string_view text, const std::string& source) {
  std::string out(text);
  enum class State { normal, comment, basic, literal, multiline_basic, multiline_literal } state = State::normal;
  std::size_t line = 1;
  for (std::size_t k = 0; k < text.size(); ++k) {
    const char c = text[k];
    const auto starts = [&](std::string_view s) { return text.substr(k, s.size()) == s; };
    if (c == '\n') {
      ++line;
      if (state == State::comment || state == State::basic || state == State::literal) state = State::normal;
      continue;
    }
    switch (state) {
      case State::normal:
        if (static_cast<unsigned char>(c) >= 0x80)
          throw CaseFileError(source + ":" + std::to_string(line) +
                              ": not valid TOML: a character that is not ASCII outside a string or comment");
        if (c == '#') state = State::comment;
        else if (starts("\"\"\"")) { state = State::multiline_basic; k += 2; }
        else if (starts("'''")) { state = State::multiline_literal; k += 2; }
        else if (c == '"') state = State::basic;
        else if (c == '\'') state = State::literal;
        break;
      case State::comment:
        if (static_cast<unsigned char>(c) >= 0x80) out[k] = '?';
        break;
      case State::basic:
        if (static_cast<unsigned char>(c) >= 0x80)
          throw CaseFileError(source + ":" + std::to_string(line) +
                              ": not valid here: a character that is not ASCII in a string (case values are ASCII)");
        if (c == '\\') ++k;
        else if (c == '"') state = State::normal;
        break;
      case State::literal:
        if (static_cast<unsigned char>(c) >= 0x80)
          throw CaseFileError(source + ":" + std::to_string(line) +
                              ": not valid here: a character that is not ASCII in a string (case values are ASCII)");
        if (c == '\'') state = State::normal;
        break;
      case State::multiline_basic:
        if (static_cast<unsigned char>(c) >= 0x80)
          throw CaseFileError(source + ":" + std::to_string(line) +
                              ": not valid here: a character that is not ASCII in a multi-line string");
        if (c == '\\') ++k;
        else if (starts("\"\"\"")) { state = State::normal; k += 2; }
        break;
      case State::multiline_literal:
        if (static_cast<unsigned char>(c) >= 0x80)
          throw CaseFileError(source + ":" + std::to_string(line) +
                              ": not valid here: a character that is not ASCII in a multi-line string");
        if (starts("'''")) { state = State::normal; k += 2; }
        break;
    }
  }
  return out;
}


bool valid_name(const std::string& name) {
  if (name.empty()) return false;
  for (char ch : name)
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '.' || ch == '-')) return false;
  return true;
}

// A point of a measurement (gauge, velocity probe) must lie in the general form's domain.
void fail_outside_domain(const Reader& r, const CaseDescription& c, const toml::node* node, const std::string& key,
                         const std::vector<double>& position) {
  if (c.domain.lower.empty()) return;
  for (int a = 0; a < c.dimension; ++a)
    if (position[std::size_t(a)] < c.domain.lower[std::size_t(a)] || position[std::size_t(a)] > c.domain.upper[std::size_t(a)])
      r.fail(node, key, "lies outside the domain (along axis " + std::to_string(a) + ")");
}

const toml::array& tables(const Reader& r, const toml::node* node, const std::string& key) {
  const toml::array* list = node->as_array();
  if (!list || !list->is_array_of_tables()) r.fail(node, key, "must be an array of tables [[" + key + "]]");
  return *list;
}

// [[shape]] tables, each checked for the keys of its type; operands must be shapes named before.
void read_shapes(const Reader& r, const toml::table& root, CaseDescription& c) {
  const toml::node* node = root.get("shape");
  if (!node) return;
  const int d = c.dimension;
  for (const toml::node& entry : tables(r, node, "shape")) {
    const toml::table& t = *entry.as_table();
    ShapeDescription shape;
    shape.line = int(t.source().begin.line);
    shape.name = r.text(t, "shape.", "name", nullptr);
    if (!valid_name(shape.name)) r.fail(t.get("name"), "shape.name", "use letters, digits, '_', '.' or '-'");
    for (const ShapeDescription& other : c.shapes)
      if (other.name == shape.name)
        r.fail(t.get("name"), "shape.name", "'" + shape.name + "' is already the name of the shape on line " + std::to_string(other.line));
    if (!t.get("type")) r.fail_at(t, "shape.type", "missing value");
    shape.type = r.choice(t, "shape.", "type",
                          {"box", "sphere", "cylinder", "half_space", "polygon", "mesh", "union", "intersection", "difference", "shell"});
    std::vector<std::string_view> keys = {"name", "type", "scale", "rotation", "axis", "pivot", "translation"};
    const auto vector_value = [&](const char* key, bool positive_entries) {
      shape.values.emplace_back(key, r.vector(t, "shape.", key, d, positive_entries));
      keys.push_back(key);
    };
    const auto positive_value = [&](const char* key) {
      shape.values.emplace_back(key, std::vector<double>{r.positive(t, "shape.", key)});
      keys.push_back(key);
    };
    const std::string& type = shape.type;
    if ((type == "cylinder" || type == "mesh") && d != 3)
      r.fail(t.get("type"), "shape.type", "\"" + type + "\" is a 3D shape; this case is 2D");
    if (type == "polygon" && d != 2) r.fail(t.get("type"), "shape.type", "\"polygon\" is a 2D shape; this case is 3D (use \"mesh\")");
    if (type == "box") {
      vector_value("lower", false);
      vector_value("upper", false);
      const std::vector<double>& lo = *shape.value("lower");
      const std::vector<double>& hi = *shape.value("upper");
      for (int a = 0; a < d; ++a)
        if (!(lo[std::size_t(a)] < hi[std::size_t(a)]))
          r.fail(t.get("upper"), "shape.upper", "must be above shape.lower along every axis (not along axis " + std::to_string(a) + ")");
    } else if (type == "sphere") {
      vector_value("center", false);
      positive_value("radius");
    } else if (type == "cylinder") {
      vector_value("start", false);
      vector_value("end", false);
      positive_value("radius");
      if (*shape.value("start") == *shape.value("end")) r.fail(t.get("end"), "shape.end", "the axis has zero length (start = end)");
    } else if (type == "half_space") {
      vector_value("point", false);
      vector_value("normal", false);
      double squared = 0;
      for (double v : *shape.value("normal")) squared += v * v;
      if (!(squared > 0)) r.fail(t.get("normal"), "shape.normal", "must not be the zero vector");
    } else if (type == "polygon" || type == "mesh") {
      keys.push_back("file");
      const std::string file = r.text(t, "shape.", "file", nullptr);
      if (file.empty()) r.fail(t.get("file"), "shape.file", "must name a geometry file");
      shape.file = (std::filesystem::path(r.source).parent_path() / file).lexically_normal().string();
    } else {
      // Booleans combine a list of shapes; shell thickens one.
      const bool shell = type == "shell";
      const char* key = shell ? "shape" : "shapes";
      keys.push_back(key);
      if (shell) {
        shape.operands.push_back(r.text(t, "shape.", "shape", nullptr));
        positive_value("thickness");
      } else {
        const toml::node* list = t.get("shapes");
        if (!list) r.fail_at(t, "shape.shapes", "missing value");
        const toml::array* names = list->as_array();
        if (!names) r.fail(list, "shape.shapes", "must be an array of shape names");
        for (const toml::node& n : *names) {
          if (!n.as_string()) r.fail(list, "shape.shapes", "must be an array of shape names (strings)");
          shape.operands.push_back(n.as_string()->get());
        }
        const std::size_t least = type == "difference" ? 2 : 1;
        if (shape.operands.size() < least)
          r.fail(list, "shape.shapes",
                 "a " + type + " of " + std::to_string(shape.operands.size()) + " shapes: it needs at least " + std::to_string(least) +
                     (type == "difference" ? " (the first minus the others)" : ""));
      }
      for (const std::string& operand : shape.operands) {
        bool found = false;
        for (const ShapeDescription& other : c.shapes) found = found || other.name == operand;
        if (!found)
          r.fail(t.get(key), std::string("shape.") + key,
                 "'" + operand + "' is not the name of a shape defined above this one");
      }
    }
    // The rigid transform: scale, then rotation about `pivot`, then translation.
    if (t.get("scale")) shape.values.emplace_back("scale", std::vector<double>{r.positive(t, "shape.", "scale")});
    if (t.get("rotation")) {
      shape.values.emplace_back("rotation", std::vector<double>{r.number(t, "shape.", "rotation", nullptr)});
      if (d == 3) {
        shape.values.emplace_back("axis", r.vector(t, "shape.", "axis", 3, false));
        double squared = 0;
        for (double v : *shape.value("axis")) squared += v * v;
        if (!(squared > 0)) r.fail(t.get("axis"), "shape.axis", "the rotation axis has zero length");
      } else if (t.get("axis")) {
        r.fail(t.get("axis"), "shape.axis", "a 2D rotation is about a point (shape.pivot); it takes no axis");
      }
      if (t.get("pivot")) shape.values.emplace_back("pivot", r.vector(t, "shape.", "pivot", d, false));
    } else {
      for (const char* key : {"axis", "pivot"})
        if (t.get(key)) r.fail(t.get(key), std::string("shape.") + key, "is read only with shape.rotation");
    }
    if (t.get("translation")) shape.values.emplace_back("translation", r.vector(t, "shape.", "translation", d, false));
    r.only_keys(t, "shape.", keys);
    c.shapes.push_back(std::move(shape));
  }
}

// [body.translation] or [body.rotation] of a wall body (case_description.hpp, MotionDescription).
MotionDescription read_motion(const Reader& r, const toml::table& body, const std::string& which, int d) {
  MotionDescription m;
  const toml::node* node = body.get(which);
  if (!node) return m;
  const std::string prefix = "body." + which + ".";
  if (!node->is_table()) r.fail(node, "body." + which, "must be a table ([body." + which + "] after the [[body]])");
  const toml::table& t = *node->as_table();
  m.line = int(t.source().begin.line);
  if (!t.get("law")) r.fail_at(t, prefix + "law", "missing value (\"constant\", \"sinusoid\" or \"table\")");
  m.law = r.choice(t, prefix, "law", {"constant", "sinusoid", "table"});
  const bool rotation = which == "rotation";
  std::vector<std::string_view> keys = {"law"};
  if (rotation) {
    m.pivot = r.vector(t, prefix, "pivot", d, false);
    keys.push_back("pivot");
    if (d == 3) {
      m.axis = r.vector(t, prefix, "axis", 3, false);
      if (m.axis[0] == 0 && m.axis[1] == 0 && m.axis[2] == 0) r.fail(t.get("axis"), prefix + "axis", "must not be the zero vector");
      keys.push_back("axis");
    }
  } else {
    m.direction = r.vector(t, prefix, "direction", d, false);
    bool zero = true;
    for (double x : m.direction) zero = zero && x == 0;
    if (zero) r.fail(t.get("direction"), prefix + "direction", "must not be the zero vector");
    keys.push_back("direction");
  }
  if (m.law == "constant") {
    m.rate = r.number(t, prefix, rotation ? "rate" : "velocity", nullptr);
    keys.push_back(rotation ? "rate" : "velocity");
  } else if (m.law == "sinusoid") {
    m.amplitude = r.number(t, prefix, "amplitude", nullptr);
    m.period = r.positive(t, prefix, "period");
    const double zero = 0;
    m.phase = r.number(t, prefix, "phase", &zero);
    m.ramp_periods = r.non_negative(t, prefix, "ramp_periods", 0.0);
    m.start = r.number(t, prefix, "start", &zero);
    for (const char* k : {"amplitude", "period", "phase", "ramp_periods", "start"}) keys.push_back(k);
  } else {
    const std::string file = r.text(t, prefix, "file", nullptr);
    m.file = (std::filesystem::path(r.source).parent_path() / file).lexically_normal().string();
    keys.push_back("file");
  }
  r.only_keys(t, prefix, keys);
  return m;
}

// [[body]] tables: fluid or wall bodies made of named shapes.
constexpr long long default_relaxation_iterations = 1500;  // RelaxationSettings' default
void read_bodies(const Reader& r, const toml::table& root, CaseDescription& c) {
  const int d = c.dimension;
  for (const toml::node& entry : tables(r, root.get("body"), "body")) {
    const toml::table& t = *entry.as_table();
    BodyDescription body;
    body.line = int(t.source().begin.line);
    body.name = r.text(t, "body.", "name", nullptr);
    if (!valid_name(body.name)) r.fail(t.get("name"), "body.name", "use letters, digits, '_', '.' or '-' (it names output files)");
    for (const BodyDescription& other : c.bodies)
      if (other.name == body.name)
        r.fail(t.get("name"), "body.name", "'" + body.name + "' is already the name of the body on line " + std::to_string(other.line));
    if (!t.get("kind")) r.fail_at(t, "body.kind", "missing value (\"fluid\" or \"wall\")");
    body.kind = r.choice(t, "body.", "kind", {"fluid", "wall"});
    body.shape = r.text(t, "body.", "shape", nullptr);
    bool found = false;
    for (const ShapeDescription& s : c.shapes) found = found || s.name == body.shape;
    if (!found) r.fail(t.get("shape"), "body.shape", "'" + body.shape + "' is not the name of a [[shape]]");
    // fill = "lattice" (default) or "relaxed" (body-fitted: shape/relaxed_particles.hpp).
    body.fill = r.choice(t, "body.", "fill", {"lattice", "relaxed"});
    if (body.fill == "relaxed") {
      const long long iterations = r.integer(t, "body.", "relaxation_iterations", &default_relaxation_iterations);
      if (iterations < 1 || iterations > 100000)
        r.fail(t.get("relaxation_iterations"), "body.relaxation_iterations",
               "must be 1 to 100000 (it is " + std::to_string(iterations) + ")");
      body.relaxation_iterations = int(iterations);
      // A relaxed fluid continues across periodic faces (shape/relaxed_particles.hpp); a wall's
      // band is relaxed against its own surface only.
      if (!c.domain.periodic.empty() && body.kind == "wall")
        r.fail(t.get("fill"), "body.fill",
               "relaxed wall bodies are not available in a periodic domain (a wall's band is relaxed without seeing "
               "across periodic faces; relaxed fluid bodies are)");
    } else if (t.get("relaxation_iterations")) {
      r.fail(t.get("relaxation_iterations"), "body.relaxation_iterations", "is read only with body.fill = \"relaxed\"");
    }
    if (body.kind == "fluid") {
      r.only_keys(t, "body.", {"name", "kind", "shape", "velocity", "fill", "relaxation_iterations"});
      body.velocity = t.get("velocity") ? r.vector(t, "body.", "velocity", d, false) : std::vector<double>(std::size_t(d), 0.0);
    } else {
      r.only_keys(t, "body.", {"name", "kind", "shape", "layers", "fill", "relaxation_iterations", "translation", "rotation"});
      body.translation = read_motion(r, t, "translation", d);
      body.rotation = read_motion(r, t, "rotation", d);
      if (body.moves() && !c.domain.periodic.empty())
        r.fail(t.get(body.translation.moves() ? "translation" : "rotation"), "body." + std::string(body.translation.moves() ? "translation" : "rotation"),
               "moving walls are not available in a periodic domain yet");
      const long long four = wall_layers;
      const long long layers = r.integer(t, "body.", "layers", &four);
      if (layers < 1 || layers > 16) r.fail(t.get("layers"), "body.layers", "must be 1 to 16 (it is " + std::to_string(layers) + ")");
      // The default layers must cover the kernel's support 2 h below a fluid particle half a
      // spacing off the wall (h <= 1.75 dx). Layers the case sets are its own (a thin plate).
      if (!t.get("layers") && double(layers) < 2 * c.smoothing_length_ratio + 0.5)
        r.fail(&t, "body.layers",
               "body '" + body.name + "' has the default " + std::to_string(layers) +
                   " layers of wall particles, fewer than the " + Reader::format(2 * c.smoothing_length_ratio + 0.5) +
                   " that cover the kernel at h / dx = " + Reader::format(c.smoothing_length_ratio) +
                   " (2 h / dx + 0.5): set body.layers");
      body.layers = int(layers);
    }
    c.bodies.push_back(std::move(body));
  }
  bool fluid = false;
  for (const BodyDescription& b : c.bodies) fluid = fluid || b.kind == "fluid";
  if (!fluid) r.fail(root.get("body"), "body.kind", "the case has no fluid body (kind = \"fluid\")");
}

// The general form: [domain], [[shape]], [[body]].
void read_general_form(const Reader& r, const toml::table& root, CaseDescription& c) {
  const toml::table& domain = r.table(root, "domain", true);
  r.only_keys(domain, "domain.", {"lower", "upper", "leaving", "periodic"});
  c.domain.lower = r.vector(domain, "domain.", "lower", c.dimension, false);
  c.domain.upper = r.vector(domain, "domain.", "upper", c.dimension, false);
  for (int a = 0; a < c.dimension; ++a)
    if (!(c.domain.lower[std::size_t(a)] < c.domain.upper[std::size_t(a)]))
      r.fail(domain.get("upper"), "domain.upper", "must be above domain.lower along every axis (not along axis " + std::to_string(a) + ")");
  c.domain.leaving = r.choice(domain, "domain.", "leaving", {"remove", "stop"});
  // domain.periodic = ["x", "y"]: the periodic axes (the solver checks the widths against the
  // cutoff and the walls against the faces, with the run's dx).
  if (const toml::node* node = domain.get("periodic")) {
    c.domain.periodic_line = int(node->source().begin.line);
    const toml::array* list = node->as_array();
    if (!list)
      r.fail(node, "domain.periodic", std::string("must be an array of axis names such as [\"x\", \"y\"] (it is a ") +
                                           Reader::type_name(*node) + ")");
    const std::string names = c.dimension == 3 ? "\"x\", \"y\" or \"z\"" : "\"x\" or \"y\"";
    for (const toml::node& e : *list) {
      const auto* name = e.as_string();
      if (!name) r.fail(node, "domain.periodic", "entries must be axis names " + names + " (one is a " + Reader::type_name(e) + ")");
      const std::string axis = name->get();
      int a = -1;
      for (int k = 0; k < c.dimension; ++k)
        if (axis == std::string(1, "xyz"[k])) a = k;
      if (a < 0) r.fail(node, "domain.periodic", "\"" + axis + "\" is not an axis of this " + std::to_string(c.dimension) + "D case (" + names + ")");
      if (c.domain.is_periodic(a)) r.fail(node, "domain.periodic", "axis \"" + axis + "\" is named twice");
      c.domain.periodic.push_back(a);
    }
    std::sort(c.domain.periodic.begin(), c.domain.periodic.end());
  }
  read_shapes(r, root, c);
  read_bodies(r, root, c);
}
}  // namespace

CaseDescription parse_case(std::string_view text, const std::string& source) {
  refuse_invalid_utf8(text, source);
  const std::string ascii = ascii_for_toml(text, source);
  refuse_headers_without_key(ascii, source);
  toml::table root;
  try {
    root = toml::parse(ascii, source);
  } catch (const toml::parse_error& e) {
    std::string what(e.description());
    for (char& c : what)
      if (c == '\n') c = ' ';
    throw CaseFileError(source + ":" + std::to_string(e.source().begin.line) + ": not valid TOML: " + what);
  }
  Reader r{source};
  r.only_keys(root, "", {"case", "geometry", "domain", "shape", "body", "fluid", "physics", "initial", "time", "report",
                         "probe", "velocity_probe", "damping_zone", "gauge", "obstacle"});
  CaseDescription c;
  c.source = source;

  const toml::table& case_table = r.table(root, "case", true);
  r.only_keys(case_table, "case.", {"name", "dimension"});
  c.name = r.text(case_table, "case.", "name", nullptr);
  const long long two = 2;
  const long long dimension = r.integer(case_table, "case.", "dimension", &two);
  if (dimension != 2 && dimension != 3)
    r.fail(case_table.get("dimension"), "case.dimension", "must be 2 or 3 (it is " + std::to_string(dimension) + ")");
  c.dimension = int(dimension);

  // The general form ([[body]]) or the short form (geometry.tank and geometry.column), not both.
  const bool general = root.get("body") != nullptr;
  const toml::table& geometry = r.table(root, "geometry", true);
  r.only_keys(geometry, "geometry.", {"dx", "tank", "column", "smoothing_length_ratio"});
  c.dx = r.positive(geometry, "geometry.", "dx");
  const double default_ratio = c.smoothing_length_ratio;
  c.smoothing_length_ratio = r.positive(geometry, "geometry.", "smoothing_length_ratio", &default_ratio);
  if (c.smoothing_length_ratio < 1 || c.smoothing_length_ratio > 2)
    r.fail(geometry.get("smoothing_length_ratio"), "geometry.smoothing_length_ratio",
           "must be 1 to 2 (h / dx; 1.3 by default; it is " + Reader::format(c.smoothing_length_ratio) + ")");
  if (general) {
    for (const char* key : {"tank", "column"})
      if (geometry.get(key))
        r.fail(geometry.get(key), std::string("geometry.") + key,
               "the short form (geometry.tank, geometry.column) and [[body]] tables cannot be mixed: describe the tank "
               "and the water as shapes and bodies");
    read_general_form(r, root, c);
  } else {
    for (const char* table : {"domain", "shape"})
      if (root.get(table))
        r.fail(root.get(table), table,
               std::string("[") + table + "] belongs to the general form, which needs [[body]] tables (none here)");
    c.tank = r.vector(geometry, "geometry.", "tank", c.dimension, true);
    c.column = r.vector(geometry, "geometry.", "column", c.dimension, true);
    for (int a = 0; a < c.dimension; ++a)
      if (c.column[a] > c.tank[a])
        r.fail(geometry.get("column"), "geometry.column",
               "the column (" + Reader::format(c.column[a]) + " along axis " + std::to_string(a) +
                   ") is larger than the tank (" + Reader::format(c.tank[a]) + ")");
    for (int a = 0; a < c.dimension; ++a)
      if (c.column[a] < c.dx)
        r.fail(geometry.get("column"), "geometry.column",
               "the column (" + Reader::format(c.column[a]) + " along axis " + std::to_string(a) +
                   ") is thinner than one particle spacing dx = " + Reader::format(c.dx));
  }

  const toml::table& fluid = r.table(root, "fluid", true);
  r.only_keys(fluid, "fluid.", {"density", "sound_speed", "reference_velocity", "viscosity", "continuity_dissipation",
                          "free_surface_density", "density_method", "density_diffusion", "kernel_gradient_correction",
                          "particle_shifting", "wall_continuity", "wall_pressure"});
  c.density = r.positive(fluid, "fluid.", "density");
  c.sound_speed = r.positive(fluid, "fluid.", "sound_speed");
  c.reference_velocity = r.positive(fluid, "fluid.", "reference_velocity");
  c.viscosity = r.non_negative(fluid, "fluid.", "viscosity", 0.0);
  c.continuity_dissipation = r.boolean(fluid, "fluid.", "continuity_dissipation", c.continuity_dissipation);
  c.kernel_gradient_correction = r.boolean(fluid, "fluid.", "kernel_gradient_correction", c.kernel_gradient_correction);
  c.free_surface_density = r.choice(fluid, "fluid.", "free_surface_density", {"reference", "carried", "none"});
  c.density_method = r.choice(fluid, "fluid.", "density_method", {"summation", "continuity"});
  c.density_diffusion = r.non_negative(fluid, "fluid.", "density_diffusion", 0.0);
  c.wall_continuity = r.choice(fluid, "fluid.", "wall_continuity", {"mirror", "kernel_sum"});
  c.wall_pressure = r.choice(fluid, "fluid.", "wall_pressure", {"extrapolated", "averaged"});
  c.particle_shifting = r.non_negative(fluid, "fluid.", "particle_shifting", 0.0);
  // Larger shifts than Lind's and SPHinXsys' A = 0.4 were not tried; a particle's shift is capped
  // at 0.1 h anyway.
  if (c.particle_shifting > 1)
    r.fail(fluid.get("particle_shifting"), "fluid.particle_shifting",
           "must be at most 1 (SPHinXsys' value is 0.4; it is " + Reader::format(c.particle_shifting) + ")");
  // An explicit diffusion with the acoustic step (docs/sph.md, "Density"): delta = 0.1 beside the
  // Riemann dissipation of the continuity equation (itself a density diffusion), or 0.15 and 0.2
  // alone, blew up the 2D dam break; the peers use 0.1 without a Riemann dissipation.
  if (c.density_diffusion > 0.1)
    r.fail(fluid.get("density_diffusion"), "fluid.density_diffusion",
           "must be at most 0.1 (larger values made the explicit diffusion blow up in the 2D dam break; delta-SPH uses 0.1)");
  if (c.density_method == "continuity" && c.continuity_dissipation)
    r.fail(fluid.get("continuity_dissipation"), "fluid.continuity_dissipation",
           "with fluid.density_method = \"continuity\" the Riemann dissipation of the continuity equation is an explicit "
           "density diffusion that nothing resets, and it blew up the 3D dam break: use fluid.density_diffusion instead");
  if (c.density_diffusion > 0 && c.continuity_dissipation)
    r.fail(fluid.get("density_diffusion"), "fluid.density_diffusion",
           "with fluid.continuity_dissipation = true the Riemann dissipation already diffuses the density, and both "
           "together blew up the 2D dam break: set one of them");

  // physics.gravity: |g| along -y (a number), or the vector g (D numbers, not all zero).
  const toml::table& physics = r.table(root, "physics", true);
  r.only_keys(physics, "physics.", {"gravity"});
  if (physics.get("gravity") && physics.get("gravity")->is_array()) {
    c.gravity_vector = r.vector(physics, "physics.", "gravity", c.dimension, false);
    double squared = 0;
    for (double g : c.gravity_vector) squared += g * g;
    c.gravity = std::sqrt(squared);
    // Zero only in a periodic domain (a vortex, a channel driven otherwise): elsewhere a mistake.
    if (!(c.gravity > 0) && c.domain.periodic.empty())
      r.fail(physics.get("gravity"), "physics.gravity", "must not be the zero vector (it may be in a periodic domain, domain.periodic)");
  } else {
    c.gravity = r.positive(physics, "physics.", "gravity");
    c.gravity_vector.assign(std::size_t(c.dimension), 0.0);
    c.gravity_vector[1] = -c.gravity;
  }

  const toml::table& initial = r.table(root, "initial", false);
  r.only_keys(initial, "initial.", {"state", "free_surface", "settling_time", "settling_damping"});
  c.hydrostatic = r.choice(initial, "initial.", "state", {"rest", "hydrostatic"}) == "hydrostatic";
  if (general) {
    // The level of the free surface along -g, for the hydrostatic start.
    if (c.hydrostatic && !(c.gravity > 0))
      r.fail(initial.get("state"), "initial.state", "a hydrostatic start needs gravity (physics.gravity is the zero vector)");
    if (c.hydrostatic) c.free_surface = r.number(initial, "initial.", "free_surface", nullptr);
    else if (initial.get("free_surface"))
      r.fail(initial.get("free_surface"), "initial.free_surface", "is read only with initial.state = \"hydrostatic\"");
  } else {
    if (initial.get("free_surface"))
      r.fail(initial.get("free_surface"), "initial.free_surface",
             "belongs to the general form ([[body]]); the short form's free surface is the column's top");
    c.free_surface = c.column[1];
  }
  c.settling_time = r.non_negative(initial, "initial.", "settling_time", 0.0);
  if (initial.get("settling_damping")) {
    c.settling_damping = r.positive(initial, "initial.", "settling_damping");
    if (!(c.settling_time > 0))
      r.fail(initial.get("settling_damping"), "initial.settling_damping", "needs initial.settling_time > 0");
  } else if (c.settling_time > 0) {
    // By default the damping's time scale is twice the column's height over the reference speed
    // (hydrostatic_2d: 1 per unit of time; twice that settled worse, docs/sph.md "Settling").
    if (general)
      r.fail(&initial, "initial.settling_damping",
             "missing value: the general form has no column to derive it from (the short form takes U over twice the "
             "column's height)");
    c.settling_damping = c.reference_velocity / (2 * c.column[1]);
  }

  const toml::table& time = r.table(root, "time", true);
  r.only_keys(time, "time.", {"end", "output_interval", "sort_every", "neighbor_search", "last_acoustic_step", "checkpoint_every",
                          "cells_per_cutoff"});
  c.end_time = r.positive(time, "time.", "end");
  const double default_interval = c.end_time / 50;
  c.output_interval = r.positive(time, "time.", "output_interval", &default_interval);
  const long long one = 1;
  const long long sort_every = r.integer(time, "time.", "sort_every", &one);
  if (sort_every < 1) r.fail(time.get("sort_every"), "time.sort_every", "must be at least 1");
  c.sort_every = int(sort_every);
  c.checkpoint_every = r.non_negative(time, "time.", "checkpoint_every", 0.0);
  c.neighbor_search = r.choice(time, "time.", "neighbor_search", {"automatic", "stored", "direct"});
  c.last_acoustic_step = r.choice(time, "time.", "last_acoustic_step", {"shortened", "full"});
  const long long automatic_cells = 0;
  const long long cells_per_cutoff = r.integer(time, "time.", "cells_per_cutoff", &automatic_cells);
  if (cells_per_cutoff < 0 || cells_per_cutoff > 2)
    r.fail(time.get("cells_per_cutoff"), "time.cells_per_cutoff",
           "must be 0 (automatic), 1 or 2 (it is " + std::to_string(cells_per_cutoff) + ")");
  c.cells_per_cutoff = int(cells_per_cutoff);

  const toml::table& report = r.table(root, "report", false);
  r.only_keys(report, "report.", {"length", "time", "pressure", "loads", "moment_point"});
  const double unit = 1;
  c.length_scale = r.positive(report, "report.", "length", &unit);
  c.time_scale = r.positive(report, "report.", "time", &unit);
  c.pressure_scale = r.positive(report, "report.", "pressure", &unit);
  // report.loads = true: every wall body's force and moment (about report.moment_point) to loads.csv.
  c.loads = r.boolean(report, "report.", "loads", c.loads);
  c.moment_point = report.get("moment_point") ? r.vector(report, "report.", "moment_point", c.dimension, false)
                                              : std::vector<double>(std::size_t(c.dimension), 0.0);
  if (report.get("moment_point") && !c.loads)
    r.fail(report.get("moment_point"), "report.moment_point", "is read only with report.loads = true");

  if (const toml::node* probes = root.get("probe")) {
    const toml::array* list = probes->as_array();
    if (!list || !list->is_array_of_tables()) r.fail(probes, "probe", "must be an array of tables [[probe]]");
    for (const toml::node& node : *list) {
      const toml::table& p = *node.as_table();
      r.only_keys(p, "probe.", {"name", "position", "kernel_width"});
      ProbeDescription probe;
      probe.name = r.text(p, "probe.", "name", nullptr);
      for (char ch : probe.name)
        if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '.' || ch == '-'))
          r.fail(p.get("name"), "probe.name", "use letters, digits, '_', '.' or '-' (it names a CSV column)");
      probe.position = r.vector(p, "probe.", "position", c.dimension, false);
      const double one = 1.0;
      probe.kernel_width = r.positive(p, "probe.", "kernel_width", &one);
      c.probes.push_back(probe);
    }
  }

  // [damping_zone]: passive wave absorption (general form: a direction in the domain's axes).
  if (const toml::node* node = root.get("damping_zone")) {
    if (!node->as_table()) r.fail(node, "damping_zone", "must be a table [damping_zone]");
    const toml::table& z = *node->as_table();
    r.only_keys(z, "damping_zone.", {"direction", "start", "end", "strength", "form"});
    DampingZoneDescription& d = c.damping_zone;
    d.direction = r.vector(z, "damping_zone.", "direction", c.dimension, false);
    double length2 = 0;
    for (double x : d.direction) length2 += x * x;
    if (!(length2 > 0)) r.fail(z.get("direction"), "damping_zone.direction", "must not be zero");
    d.start = r.number(z, "damping_zone.", "start", nullptr);
    d.end = r.number(z, "damping_zone.", "end", nullptr);
    if (!(d.end > d.start)) r.fail(z.get("end"), "damping_zone.end", "must be beyond damping_zone.start");
    d.strength = r.non_negative(z, "damping_zone.", "strength", 0.0);
    if (!z.get("strength")) r.fail(&z, "damping_zone.strength", "missing value");
    d.form = r.choice(z, "damping_zone.", "form", {"linear", "exponential"});
  }

  // [[velocity_probe]]: points inside the domain, names unique (they name CSV columns).
  if (const toml::node* probes = root.get("velocity_probe")) {
    const toml::array* list = probes->as_array();
    if (!list || !list->is_array_of_tables())
      r.fail(probes, "velocity_probe", "must be an array of tables [[velocity_probe]]");
    for (const toml::node& node : *list) {
      const toml::table& p = *node.as_table();
      r.only_keys(p, "velocity_probe.", {"name", "position"});
      VelocityProbeDescription probe;
      probe.name = r.text(p, "velocity_probe.", "name", nullptr);
      if (!valid_name(probe.name))
        r.fail(p.get("name"), "velocity_probe.name", "use letters, digits, '_', '.' or '-' (it names a CSV column)");
      for (const VelocityProbeDescription& other : c.velocity_probes)
        if (other.name == probe.name)
          r.fail(p.get("name"), "velocity_probe.name", "'" + probe.name + "' names two velocity probes");
      probe.position = r.vector(p, "velocity_probe.", "position", c.dimension, false);
      fail_outside_domain(r, c, p.get("position"), "velocity_probe.position", probe.position);
      c.velocity_probes.push_back(probe);
    }
  }

  // [[gauge]]: wave gauges (their lines must lie in the domain; the levels are checked against the
  // gravity vector when the solver makes them).
  if (const toml::node* gauges = root.get("gauge")) {
    const toml::array* list = gauges->as_array();
    if (!list || !list->is_array_of_tables()) r.fail(gauges, "gauge", "must be an array of tables [[gauge]]");
    for (const toml::node& node : *list) {
      const toml::table& g = *node.as_table();
      r.only_keys(g, "gauge.", {"name", "position", "bottom", "top"});
      GaugeDescription gauge;
      gauge.line = int(g.source().begin.line);
      gauge.name = r.text(g, "gauge.", "name", nullptr);
      if (!valid_name(gauge.name)) r.fail(g.get("name"), "gauge.name", "use letters, digits, '_', '.' or '-' (it names a CSV column)");
      for (const GaugeDescription& other : c.gauges)
        if (other.name == gauge.name) r.fail(g.get("name"), "gauge.name", "'" + gauge.name + "' names two gauges");
      gauge.position = r.vector(g, "gauge.", "position", c.dimension, false);
      gauge.bottom = r.number(g, "gauge.", "bottom", nullptr);
      gauge.top = r.number(g, "gauge.", "top", nullptr);
      if (!(gauge.top > gauge.bottom)) r.fail(g.get("top"), "gauge.top", "must be above gauge.bottom");
      fail_outside_domain(r, c, g.get("position"), "gauge.position", gauge.position);
      c.gauges.push_back(gauge);
    }
  }

  // [[obstacle]]: a particle file of `unisph generate`, named relative to the case file. The
  // file itself is read and checked when the solver is made (obstacle_particles.hpp), with the
  // dx of the run (--dx may override geometry.dx).
  if (const toml::node* obstacles = root.get("obstacle")) {
    const toml::array* list = obstacles->as_array();
    if (!list || !list->is_array_of_tables()) r.fail(obstacles, "obstacle", "must be an array of tables [[obstacle]]");
    for (const toml::node& node : *list) {
      const toml::table& o = *node.as_table();
      r.only_keys(o, "obstacle.", {"file", "translation"});
      ObstacleDescription obstacle;
      const std::string file = r.text(o, "obstacle.", "file", nullptr);
      if (file.empty()) r.fail(o.get("file"), "obstacle.file", "must name a particle file (.vtp of `unisph generate`)");
      obstacle.file = (std::filesystem::path(source).parent_path() / file).lexically_normal().string();
      obstacle.line = int(o.get("file")->source().begin.line);
      obstacle.translation = o.get("translation") ? r.vector(o, "obstacle.", "translation", c.dimension, false)
                                                  : std::vector<double>(std::size_t(c.dimension), 0.0);
      c.obstacles.push_back(obstacle);
    }
  }
  // The short form's tank and the obstacles have wall_layers (4) layers of wall particles.
  const double covered_ratio = (wall_layers - 0.5) / 2;  // layers >= 2 h / dx + 0.5
  if ((!general || !c.obstacles.empty()) && c.smoothing_length_ratio > covered_ratio)
    r.fail(geometry.get("smoothing_length_ratio"), "geometry.smoothing_length_ratio",
           std::string(general ? "the obstacles have " : "the short form's tank has ") + std::to_string(wall_layers) +
               " layers of wall particles, which cover h up to " + Reader::format(covered_ratio) + " dx (it is " +
               Reader::format(c.smoothing_length_ratio) + ")");
  return c;
}

CaseDescription read_case_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CaseFileError(path + ": cannot open the case file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_case(text.str(), path);
}

}  // namespace unisph::sph
