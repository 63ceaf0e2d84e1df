#pragma once
// Reading a case file (TOML). Every error is one line naming the file, the line and the key:
//   cases/x.toml:12: key 'geometry.dx': must be positive (it is -0.01)
// and is thrown as CaseFileError before anything is written.
#include <string>
#include <string_view>

#include "unisph/core/error.hpp"
#include "unisph/solver/case_description.hpp"

namespace unisph::sph {

class CaseFileError : public Error {
 public:
  using Error::Error;
};

// Parses TOML text; `source` names it in messages.
CaseDescription parse_case(std::string_view text, const std::string& source);
// Reads and parses a file.
CaseDescription read_case_file(const std::string& path);

}  // namespace unisph::sph
