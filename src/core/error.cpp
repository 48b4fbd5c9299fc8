#include "isoquad/error.hpp"

#include <fmt/format.h>

#include "isoquad/version.hpp"

namespace isoquad {

std::string_view to_string(ErrorKind kind) {
  switch (kind) {
    case ErrorKind::invalid_input:
      return "invalid input";
    case ErrorKind::unsupported_topology:
      return "unsupported topology";
    case ErrorKind::layout:
      return "layout failed";
    case ErrorKind::solver:
      return "solver failed";
    case ErrorKind::extraction:
      return "extraction failed";
    case ErrorKind::internal:
      return "internal error";
  }
  return "error";
}

namespace {
// "file:line: message" or "file (byte 123): message", the way compilers report.
std::string located(const std::string& message, const ErrorContext& ctx) {
  if (ctx.file.empty()) return message;
  if (ctx.line >= 0) return fmt::format("{}:{}: {}", ctx.file, ctx.line, message);
  if (ctx.byte_offset >= 0)
    return fmt::format("{} (byte {}): {}", ctx.file, ctx.byte_offset, message);
  return fmt::format("{}: {}", ctx.file, message);
}
}  // namespace

Error::Error(ErrorKind kind, std::string code, const std::string& message, ErrorContext context)
    : std::runtime_error(fmt::format("{} [{}]", located(message, context), code)),
      kind_(kind),
      code_(std::move(code)),
      context_(std::move(context)) {}

const char* version() { return ISOQUAD_VERSION_STRING; }

}  // namespace isoquad
