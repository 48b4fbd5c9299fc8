// isoquad's error model: the library never prints and never exits; every failure is an
// isoquad::Error that says what went wrong, where (file, line or byte offset) and which
// elements (input vertex and face ids, 0-based). Only the command line prints it.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace isoquad {

// Failure kinds. The value is the command line's exit status (DESIGN.md §0.4).
enum class ErrorKind : int {
  invalid_input = 2,         // unreadable or malformed file, non-manifold, ...
  unsupported_topology = 3,  // valid mesh the method cannot handle (e.g. non-orientable)
  layout = 4,                // no feasible quad layout
  solver = 5,                // a linear or integer solver failed
  extraction = 6,            // quad extraction failed
  internal = 70,             // an invariant was violated: a bug in isoquad
};

std::string_view to_string(ErrorKind kind);

// Where an error was found. Empty fields are unknown or not applicable.
struct ErrorContext {
  std::string file;
  int64_t line = -1;               // 1-based line in a text file
  int64_t byte_offset = -1;        // 0-based offset in a binary file
  std::vector<uint32_t> vertices;  // input vertex ids, 0-based
  std::vector<uint32_t> faces;     // input face ids, 0-based
};

class Error : public std::runtime_error {
 public:
  // `code` is a stable short identifier (E012, E101, ...) listed in the README;
  // `message` is a full sentence that names the elements and, where there is one, a remedy.
  Error(ErrorKind kind, std::string code, const std::string& message, ErrorContext context = {});

  ErrorKind kind() const { return kind_; }
  const std::string& code() const { return code_; }
  const ErrorContext& context() const { return context_; }
  int exit_status() const { return static_cast<int>(kind_); }

 private:
  ErrorKind kind_;
  std::string code_;
  ErrorContext context_;
};

}  // namespace isoquad
