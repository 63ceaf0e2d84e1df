#pragma once
// The exceptions unisph throws. Every message is one line that says what failed and on what.

#include <stdexcept>
#include <string>

namespace unisph {

// Base of every unisph error, so that a program can catch them in one place.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An execution policy was asked for that this build or this machine does not offer.
class PolicyUnavailable : public Error {
 public:
  using Error::Error;
};

// A CUDA call failed (out of memory, failed launch, ...). The message names the operation,
// the variable or algorithm it served and the size involved, then CUDA's own words.
class DeviceError : public Error {
 public:
  using Error::Error;
};

// A variable was used against its contract (wrong type for a name, out-of-range size...).
class VariableError : public Error {
 public:
  using Error::Error;
};

}  // namespace unisph
