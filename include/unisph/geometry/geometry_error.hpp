#pragma once
// The error every geometry reader throws: one line, "<file>: <what is wrong>", so that a
// program can print it as it is and stop. Nothing is returned from a file that failed.

#include <string>

#include "unisph/core/error.hpp"

namespace unisph {

class GeometryError : public Error {
 public:
  using Error::Error;
};

}  // namespace unisph
