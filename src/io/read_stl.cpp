// STL, ascii and binary. Every facet has its own three vertices (the result is flagged so that
// preparation welds them). A file that starts with "solid" but whose size is exactly that of a
// binary STL with the count in its header is binary: many exporters write such headers.
#include <fmt/format.h>
#include <cstring>

#include "io/parse_util.hpp"

namespace isoquad::io {

namespace {

ReadResult read_binary(std::string_view bytes, const std::string& file,
                       const ReadOptions& options) {
  ReadResult result;
  result.format = MeshFormat::stl;
  result.binary = true;
  result.unshared_vertices = true;
  if (bytes.size() < 84)
    fail_at_byte(
        file, int64_t(bytes.size()), kTruncated,
        fmt::format("a binary STL needs an 84-byte header; the file has {} bytes", bytes.size()));
  uint32_t n = 0;
  std::memcpy(&n, bytes.data() + 80, 4);  // little endian on every platform we build for
  const uint64_t need = 84 + 50ull * n;
  if (bytes.size() < need)
    fail_at_byte(
        file, int64_t(84 + 50ull * ((bytes.size() - 84) / 50)), kTruncated,
        fmt::format("the header declares {} triangles ({} bytes) but the file has {} bytes", n,
                    need, bytes.size()));
  if (bytes.size() > need)
    fail_at_byte(file, int64_t(need), kCountMismatch,
                 fmt::format("{} bytes follow the {} declared triangles", bytes.size() - need, n));
  FaceChecker faces{options, result, {}};
  result.mesh.positions.reserve(3ull * n);
  for (uint32_t t = 0; t < n; ++t) {
    const char* rec = bytes.data() + 84 + 50ull * t;
    auto where = [&](const char* code, const std::string& msg) {
      fail_at_byte(file, rec - bytes.data(), code, fmt::format("triangle {}: {}", t, msg));
    };
    for (int c = 0; c < 3; ++c) {
      float xyz[3];
      std::memcpy(xyz, rec + 12 + 12 * c, 12);
      add_vertex(result.mesh, Vec3{xyz[0], xyz[1], xyz[2]}, where);
    }
    const int64_t base = int64_t(3) * t;
    const int64_t idx[3] = {base, base + 1, base + 2};
    faces.add(idx, where);
  }
  return result;
}

ReadResult read_ascii(std::string_view text, const std::string& file, const ReadOptions& options) {
  ReadResult result;
  result.format = MeshFormat::stl;
  result.unshared_vertices = true;
  TextCursor cur(text, file);
  FaceChecker faces{options, result, {}};
  auto where = [&](const char* code, const std::string& msg) { cur.fail(code, msg); };
  std::string_view tok;
  auto expect_line = [&](std::string_view keyword) {
    if (!cur.next_line(false))
      fail_at_line(file, cur.line_number(), kTruncated,
                   fmt::format("the file ends where '{}' was expected", keyword));
    cur.next_token(tok);
    if (tok != keyword)
      cur.fail(kSyntax, fmt::format("expected '{}' but found '{}'", keyword, tok));
  };
  expect_line("solid");
  bool ended = false;
  while (cur.next_line(false)) {
    cur.next_token(tok);
    if (tok == "endsolid") {
      ended = true;
      break;
    }
    if (tok != "facet")
      cur.fail(kSyntax, fmt::format("expected 'facet' or 'endsolid' but found '{}'", tok));
    expect_line("outer");
    int64_t idx[3];
    for (int c = 0; c < 3; ++c) {
      expect_line("vertex");
      Vec3 p;
      for (int k = 0; k < 3; ++k)
        p[k] = cur.parse_double(cur.expect_token("a coordinate"), "coordinate");
      idx[c] = int64_t(result.mesh.num_vertices());
      add_vertex(result.mesh, p, where);
    }
    expect_line("endloop");
    expect_line("endfacet");
    faces.add(idx, where);
  }
  if (!ended) fail_at_line(file, cur.line_number(), kTruncated, "the file ends without 'endsolid'");
  return result;
}

}  // namespace

ReadResult read_stl(std::string_view bytes, const std::string& file, const ReadOptions& options) {
  bool binary = true;
  const std::size_t first = bytes.find_first_not_of(" \t\r\n");
  if (first != std::string_view::npos && bytes.substr(first, 5) == "solid") {
    binary = false;
    if (bytes.size() >= 84) {
      uint32_t n = 0;
      std::memcpy(&n, bytes.data() + 80, 4);
      binary = bytes.size() == 84 + 50ull * n;
    }
  }
  return binary ? read_binary(bytes, file, options) : read_ascii(bytes, file, options);
}

}  // namespace isoquad::io
