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
    const std::size_t d = std::size_t(c.dimension);
    if (c.dx <= 0 || c.gravity_vector.size() != d) std::abort();
    if (c.general()) {
      // The reader promised a domain with lower < upper, and bodies naming shapes defined in the file.
      if (c.domain.lower.size() != d || c.domain.upper.size() != d || !c.tank.empty()) std::abort();
      for (std::size_t a = 0; a < d; ++a)
        if (!(c.domain.lower[a] < c.domain.upper[a])) std::abort();
      for (const auto& b : c.bodies) {
        bool found = false;
        for (const auto& s : c.shapes) found = found || s.name == b.shape;
        if (!found) std::abort();
      }
    } else {
      if (c.tank.size() != d || c.column.size() != d) std::abort();
      for (std::size_t a = 0; a < d; ++a)
        if (!(c.column[a] <= c.tank[a])) std::abort();  // the reader promised a column inside the tank
    }
  } catch (const unisph::sph::CaseFileError& e) {
    if (std::string_view(e.what()).find('\n') != std::string_view::npos) std::abort();  // one line
  }
  return 0;
}
