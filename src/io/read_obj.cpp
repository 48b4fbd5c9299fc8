// Wavefront OBJ: `v x y z [w]` and `f` with `i`, `i/t`, `i//n`, `i/t/n`, negative (relative)
// indices and polygons. Other statements (vt, vn, g, o, s, usemtl, mtllib, l, p) carry nothing
// the remesher uses and are skipped; an unknown statement is reported.
#include <fmt/format.h>

#include "io/parse_util.hpp"

namespace isoquad::io {

namespace {
bool is_ignored_statement(std::string_view s) {
  static constexpr std::string_view kIgnored[] = {
      "vt",         "vn",        "vp",    "g",        "o",        "s",      "usemtl",
      "mtllib",     "l",         "p",     "mg",       "maplib",   "usemap", "lod",
      "shadow_obj", "trace_obj", "bevel", "c_interp", "d_interp", "cstype", "deg",
      "curv",       "curv2",     "surf",  "parm",     "trim",     "hole",   "scrv",
      "sp",         "end",       "con",   "bmat",     "step",     "ctech",  "stech"};
  for (std::string_view k : kIgnored)
    if (s == k) return true;
  return false;
}
}  // namespace

ReadResult read_obj(std::string_view text, const std::string& file, const ReadOptions& options) {
  ReadResult result;
  result.format = MeshFormat::obj;
  TextCursor cur(text, file);
  FaceChecker faces{options, result, {}};
  std::vector<int64_t> idx;
  auto where = [&](const char* code, const std::string& msg) { cur.fail(code, msg); };
  std::string_view tok;
  while (cur.next_line()) {
    cur.next_token(tok);
    if (tok == "v") {
      Vec3 p;
      for (int i = 0; i < 3; ++i)
        p[i] = cur.parse_double(cur.expect_token("a coordinate"), "coordinate");
      add_vertex(result.mesh, p, where);
    } else if (tok == "f" || tok == "fo") {
      idx.clear();
      const auto nv = static_cast<int64_t>(result.mesh.num_vertices());
      while (cur.next_token(tok)) {
        const std::string_view head = tok.substr(0, tok.find('/'));
        const int64_t i = cur.parse_int(head, "vertex index");
        if (i == 0) cur.fail(kIndexRange, "vertex index 0 is invalid (OBJ indices start at 1)");
        idx.push_back(i > 0 ? i - 1 : nv + i);  // negative: relative to the vertices so far
        if (i < 0 && nv + i < 0)
          cur.fail(kIndexRange, fmt::format("relative vertex index {} reaches before the first "
                                            "vertex ({} vertices so far)",
                                            i, nv));
      }
      if (idx.size() < 3)
        cur.fail(kDegenerateFace,
                 fmt::format("face has {} vertices; a face needs at least 3", idx.size()));
      faces.add(idx, where);
    } else if (!is_ignored_statement(tok)) {
      cur.fail(kSyntax, fmt::format("unknown OBJ statement '{}'", tok));
    }
  }
  return result;
}

}  // namespace isoquad::io
