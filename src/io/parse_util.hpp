// Shared pieces of the readers: a cursor over text with line numbers, number parsing with
// precise errors, and the face checks every format applies. Internal to src/io.
#pragma once

#include <charconv>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/poly_mesh.hpp"
#include "io/read_mesh.hpp"
#include "isoquad/error.hpp"

namespace isoquad::io {

// Error codes of malformed input, stable and listed in the README.
inline constexpr const char* kUnreadable = "E001";
inline constexpr const char* kUnknownFormat = "E002";
inline constexpr const char* kSyntax = "E010";
inline constexpr const char* kTruncated = "E011";
inline constexpr const char* kIndexRange = "E012";
inline constexpr const char* kNonFinite = "E013";
inline constexpr const char* kDegenerateFace = "E014";
inline constexpr const char* kCountMismatch = "E015";
inline constexpr const char* kEmpty = "E016";

[[noreturn]] void fail_at_line(const std::string& file, int64_t line, const char* code,
                               const std::string& message,
                               std::initializer_list<uint32_t> faces = {});
[[noreturn]] void fail_at_byte(const std::string& file, int64_t offset, const char* code,
                               const std::string& message);

// Line-by-line cursor over a text buffer; tokens split on blanks.
class TextCursor {
 public:
  TextCursor(std::string_view text, const std::string& file) : text_(text), file_(file) {}
  // Next line with comments (from '#') stripped; skips blank lines. False at the end.
  bool next_line(bool strip_comments = true);
  bool next_token(std::string_view& token);  // within the current line
  std::string_view rest() const { return line_.substr(pos_); }
  int64_t line_number() const { return line_no_; }
  std::size_t offset() const { return next_; }  // byte offset just past the current line
  const std::string& file() const { return file_; }

  [[noreturn]] void fail(const char* code, const std::string& message) const {
    fail_at_line(file_, line_no_, code, message);
  }
  double parse_double(std::string_view token, std::string_view what) const;
  int64_t parse_int(std::string_view token, std::string_view what) const;
  std::string_view expect_token(std::string_view what);

 private:
  std::string_view text_;
  const std::string& file_;
  std::size_t next_ = 0;
  std::string_view line_;
  std::size_t pos_ = 0;
  int64_t line_no_ = 0;
};

// Validates a face given as 0-based indices and appends it: indices must be in range (E012)
// and, after removing cyclically repeated neighbours, at least 3 distinct with no repeats (E014).
// Returns false when the face was dropped (only with options.drop_degenerate_faces).
struct FaceChecker {
  const ReadOptions& options;
  ReadResult& result;
  std::vector<uint32_t> scratch;

  // `where` reports a failure at the caller's location.
  template <class Fail>
  void add(std::span<const int64_t> indices, Fail&& where) {
    const auto nv = static_cast<int64_t>(result.mesh.num_vertices());
    scratch.clear();
    for (int64_t i : indices) {
      if (i < 0 || i >= nv)
        where(kIndexRange, "face references vertex " + std::to_string(i) + " but the file has " +
                               std::to_string(nv) + " vertices (valid: 0.." +
                               std::to_string(nv - 1) + ")");
      if (scratch.empty() || scratch.back() != uint32_t(i)) scratch.push_back(uint32_t(i));
    }
    while (scratch.size() > 1 && scratch.back() == scratch.front()) scratch.pop_back();
    if (!distinct(scratch)) {
      if (options.drop_degenerate_faces) {
        ++result.dropped_faces;
        return;
      }
      where(kDegenerateFace,
            "face " + std::to_string(result.mesh.num_faces() + result.dropped_faces) +
                " has fewer than 3 distinct vertices (use --repair to drop such faces)");
    }
    result.mesh.add_face(scratch);
  }

 private:
  static bool distinct(const std::vector<uint32_t>& v);
};

// Appends a vertex after checking it is finite (E013).
template <class Fail>
void add_vertex(PolyMesh& mesh, Vec3 p, Fail&& where) {
  if (!is_finite(p))
    where(kNonFinite,
          "vertex " + std::to_string(mesh.num_vertices()) + " has a NaN or infinite coordinate");
  mesh.positions.push_back(p);
}

ReadResult read_obj(std::string_view text, const std::string& file, const ReadOptions& options);
ReadResult read_off(std::string_view text, const std::string& file, const ReadOptions& options);
ReadResult read_ply(std::string_view bytes, const std::string& file, const ReadOptions& options);
ReadResult read_stl(std::string_view bytes, const std::string& file, const ReadOptions& options);

}  // namespace isoquad::io
