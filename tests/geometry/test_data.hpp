#pragma once
// Where the geometry tests find their files: $UNISPH_TEST_DATA_DIR when set (a copy of the tree
// on another machine), else the source tree's tests/data (compile definition).
#include <cstdlib>
#include <string>

namespace unisph::testing {

inline std::string test_data(const std::string& relative) {
  const char* override_dir = std::getenv("UNISPH_TEST_DATA_DIR");
  return std::string(override_dir ? override_dir : UNISPH_TEST_DATA_DIR) + "/" + relative;
}

}  // namespace unisph::testing
