// Errors are values with context: every failure the course can meet becomes one of these
// exceptions, and run_main() turns it into one clear line and a non-zero exit code.
#pragma once

#include <stdexcept>
#include <string>

namespace rt {

// Base of every error the course reports.
class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// Bad command-line values: exit code 2, like a usage error.
class UsageError : public Error {
public:
  using Error::Error;
};

// Input that cannot be used (missing file, malformed data, absurd sizes).
class InputError : public Error {
public:
  using Error::Error;
};

// Output that cannot be written (unwritable path, full disk).
class OutputError : public Error {
public:
  using Error::Error;
};

// The GPU backend was requested but no usable CUDA device exists.
class NoGpuError : public Error {
public:
  using Error::Error;
};

} // namespace rt
