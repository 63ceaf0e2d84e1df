#pragma once
// Case-file texts for tests: a file's whole text, and the same text with one piece replaced
// (a test failure names a piece the text lacks).
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace unisph::testing {

inline std::string file_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "the test's case text lacks: " << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

}  // namespace unisph::testing
