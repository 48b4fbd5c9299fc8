// OFF (Geomview): optional ST/C/N/4 prefixes, counts on the header line or the next, one vertex
// per line (extra values such as colours ignored), one face per line `n i0 .. i(n-1) [colour]`.
#include <fmt/format.h>

#include "io/parse_util.hpp"

namespace isoquad::io {

ReadResult read_off(std::string_view text, const std::string& file, const ReadOptions& options) {
  ReadResult result;
  result.format = MeshFormat::off;
  TextCursor cur(text, file);
  auto where = [&](const char* code, const std::string& msg) { cur.fail(code, msg); };
  if (!cur.next_line()) fail_at_line(file, 1, kEmpty, "empty file");
  std::string_view tok;
  cur.next_token(tok);
  const bool is_off = tok.size() >= 3 && tok.substr(tok.size() - 3) == "OFF";
  if (!is_off) cur.fail(kSyntax, fmt::format("expected the OFF header but found '{}'", tok));
  if (tok.find('4') != std::string_view::npos || tok.find('n') != std::string_view::npos)
    cur.fail(kUnknownFormat, fmt::format("'{}' (4D or n-dimensional OFF) is not supported", tok));
  if (cur.next_token(tok)) {
    if (tok == "BINARY")
      cur.fail(kUnknownFormat, "binary OFF is not supported; convert it to ascii");
  } else {
    if (!cur.next_line()) cur.fail(kTruncated, "the file ends before the vertex and face counts");
    cur.next_token(tok);
  }
  const int64_t nv = cur.parse_int(tok, "vertex count");
  const int64_t nf = cur.parse_int(cur.expect_token("the face count"), "face count");
  if (nv < 0 || nf < 0) cur.fail(kSyntax, "negative vertex or face count");
  // Reserve only what the file can hold, so a corrupt count cannot exhaust memory.
  result.mesh.positions.reserve(std::size_t(std::min<int64_t>(nv, int64_t(text.size() / 6))));

  for (int64_t i = 0; i < nv; ++i) {
    if (!cur.next_line())
      fail_at_line(
          file, cur.line_number(), kCountMismatch,
          fmt::format("the header declares {} vertices but the file ends after {}", nv, i));
    Vec3 p;
    for (int k = 0; k < 3; ++k)
      p[k] = cur.parse_double(cur.expect_token("a coordinate"), "coordinate");
    add_vertex(result.mesh, p, where);
  }
  FaceChecker faces{options, result, {}};
  std::vector<int64_t> idx;
  for (int64_t f = 0; f < nf; ++f) {
    if (!cur.next_line())
      fail_at_line(file, cur.line_number(), kCountMismatch,
                   fmt::format("the header declares {} faces but the file ends after {}", nf, f));
    const int64_t n = cur.parse_int(cur.expect_token("the face size"), "face size");
    if (n < 3)
      cur.fail(kDegenerateFace,
               fmt::format("face {} has {} vertices; a face needs at least 3", f, n));
    idx.clear();
    for (int64_t k = 0; k < n; ++k)
      idx.push_back(cur.parse_int(cur.expect_token("a vertex index"), "vertex index"));
    faces.add(idx, where);
  }
  if (cur.next_line())
    cur.fail(kCountMismatch, fmt::format("unexpected data after the {} vertices and {} faces the "
                                         "header declares",
                                         nv, nf));
  return result;
}

}  // namespace isoquad::io
