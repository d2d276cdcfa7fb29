#pragma once
// Errors with context: which stage, which frame, which file. Library code throws; only cli/
// turns an error into a message and an exit code (never exit() in a library).
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

namespace pluvia {

struct ErrorContext {
  // Default member initialisers let a context name only its stage ({"rain"}) without
  // -Wmissing-field-initializers.
  std::string stage = {};             // "fog", "read", "preset" ...
  std::optional<int64_t> frame = {};  // frame number as in the clip (1001 stays 1001)
  std::string file = {};              // file the error is about
};

// A runtime failure (exit code 1): bad input file, failed write, GL failure.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message, ErrorContext context = {});
  const ErrorContext& context() const { return context_; }
  // "[fog @ frame 1012] message (file: a.exr)"
  std::string describe() const;

 private:
  ErrorContext context_;
};

// A mistake on the command line (exit code 2).
class UsageError : public Error {
 public:
  using Error::Error;
};

}  // namespace pluvia
