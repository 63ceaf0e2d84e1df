// libFuzzer target over the case-file reader (scripts/fuzz_case.sh): any input either parses
// into a case description or is refused with a one-line CaseFileError; nothing else may happen
// (no crash, hang, other exception, leak or sanitizer report).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "unisph/solver/case_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const unisph::sph::CaseDescription c = unisph::sph::parse_case(text, "fuzz.toml");
    if (c.dx <= 0 || c.tank.size() != std::size_t(c.dimension) || c.column.size() != std::size_t(c.dimension)) std::abort();
    for (int a = 0; a < c.dimension; ++a)
      if (!(c.column[a] <= c.tank[a])) std::abort();  // the reader promised a column inside the tank
  } catch (const unisph::sph::CaseFileError& e) {
    if (std::string_view(e.what()).find('\n') != std::string_view::npos) std::abort();  // one line
  }
  return 0;
}
