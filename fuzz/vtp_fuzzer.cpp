// libFuzzer target over the .vtp reader (scripts/fuzz_vtp.sh): any input either parses into a
// point set whose arrays hold one tuple per point (point arrays) and only finite values, or is
// refused with a one-line VtkReadError; nothing else may happen (no crash, hang, other
// exception, leak or sanitizer report).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "unisph/io/vtk_xml_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string content(reinterpret_cast<const char*>(data), size);
  try {
    const unisph::io::PolyDataFile f = unisph::io::parse_vtp(content, "fuzz.vtp");
    if (f.coordinates.size() != 3 * f.points) std::abort();
    for (const unisph::io::VtkArray& a : f.point_arrays)
      if (a.values.size() != f.points * std::uint64_t(a.components)) std::abort();
    for (double v : f.coordinates)
      if (!std::isfinite(v)) std::abort();
  } catch (const unisph::io::VtkReadError& e) {
    if (std::string(e.what()).find('\n') != std::string::npos) std::abort();  // one line
  }
  return 0;
}
