#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/edge_groups.hpp"
#include "core/union_find.hpp"
#include "isoquad/error.hpp"
#include "prep/steps.hpp"

namespace isoquad::prep {

namespace {

uint32_t corner_of(const Tri& t, uint32_t v) { return t[0] == v ? 0 : (t[1] == v ? 1 : 2); }

// Of the faces on a non-manifold edge, keeps glued the first pair that runs in opposite
// directions (or the first two): the other faces are detached from this edge.
std::pair<uint32_t, uint32_t> glued_pair(std::span<const EdgeHalfedge> g, const Soup& s) {
  for (std::size_t i = 0; i < g.size(); ++i)
    for (std::size_t j = i + 1; j < g.size(); ++j)
      if (s.tris[g[i].h / 3][g[i].h % 3] != s.tris[g[j].h / 3][g[j].h % 3]) return {g[i].h, g[j].h};
  return {g[0].h, g[1].h};
}

void report_non_manifold(const Soup& s, const std::vector<std::span<const EdgeHalfedge>>& bad,
                         const PrepOptions& options, InputReport& report) {
  const auto& g = bad.front();
  std::vector<uint32_t> faces;
  for (const auto& e : g) faces.push_back(s.tri_input[e.h / 3]);
  const uint32_t a = s.vertex_input[g[0].lo], b = s.vertex_input[g[0].hi];
  const std::string what = fmt::format(
      "non-manifold edge: {} edge{} shared by more than 2 faces (first: input vertices {}-{}; "
      "faces {})",
      bad.size(), bad.size() == 1 ? " is" : "s are", a, b, fmt::join(faces, ", "));
  report.non_manifold_edges = uint32_t(bad.size());
  if (options.repair) {
    report.issues.push_back({InputIssue::Severity::repaired, "W101",
                             what + "; detached the extra faces", uint32_t(bad.size())});
    return;
  }
  const std::string msg = what + ". Re-run with --repair to detach them, or fix the mesh.";
  if (options.diagnose) {
    report.issues.push_back({InputIssue::Severity::error, "E101", msg, uint32_t(bad.size())});
    return;
  }
  ErrorContext ctx;
  ctx.vertices = {a, b};
  ctx.faces = faces;
  throw Error(ErrorKind::invalid_input, "E101", msg, ctx);
}

// Gives every fan of every vertex its own vertex: corners are merged across glued edges only.
void split_fans(Soup& s, const std::vector<std::pair<uint32_t, uint32_t>>& glued,
                InputReport& report) {
  UnionFind corners(3 * s.tris.size());  // over triangle corners 3t + i
  for (const auto& [h0, h1] : glued) {
    const Tri &t0 = s.tris[h0 / 3], &t1 = s.tris[h1 / 3];
    for (uint32_t v : {t0[h0 % 3], t0[(h0 % 3 + 1) % 3]})
      corners.unite(3 * (h0 / 3) + corner_of(t0, v), 3 * (h1 / 3) + corner_of(t1, v));
  }
  std::vector<uint32_t> class_vertex(3 * s.tris.size(), kInvalid);
  std::vector<Vec3> positions;
  std::vector<uint32_t> vertex_input;
  std::vector<char> seen(s.positions.size(), 0);
  for (uint32_t c = 0; c < class_vertex.size(); ++c) {
    const uint32_t root = corners.find(c);
    const uint32_t old = s.tris[c / 3][c % 3];
    if (class_vertex[root] == kInvalid) {
      class_vertex[root] = uint32_t(positions.size());
      positions.push_back(s.positions[old]);
      vertex_input.push_back(s.vertex_input[old]);
      if (seen[old]) ++report.split_vertices;
      seen[old] = 1;
    }
  }
  for (uint32_t c = 0; c < class_vertex.size(); ++c)
    s.tris[c / 3][c % 3] = class_vertex[corners.find(c)];
  s.positions = std::move(positions);
  s.vertex_input = std::move(vertex_input);
}

}  // namespace

void make_manifold(Soup& s, const PrepOptions& options, InputReport& report) {
  const uint32_t split_before = report.split_vertices;
  for (int round = 0;; ++round) {
    const auto keys = halfedges_by_edge(s.tris);
    std::vector<std::pair<uint32_t, uint32_t>> glued;
    std::vector<std::span<const EdgeHalfedge>> bad;
    for_each_edge_group(keys, [&](std::span<const EdgeHalfedge> g) {
      if (g.size() == 2) glued.push_back({g[0].h, g[1].h});
      if (g.size() > 2) {
        bad.push_back(g);
        glued.push_back(glued_pair(g, s));
      }
    });
    if (!bad.empty() && round == 0) report_non_manifold(s, bad, options, report);
    if (!bad.empty() && round > 0) {
      // Detaching left a face on the edge through another fan: remove it (rare).
      std::vector<char> drop(s.tris.size(), 0);
      for (const auto& g : bad) {
        const auto [h0, h1] = glued_pair(g, s);
        for (const auto& e : g)
          if (e.h != h0 && e.h != h1) drop[e.h / 3] = 1;
      }
      std::size_t out = 0;
      for (std::size_t t = 0; t < s.tris.size(); ++t) {
        if (drop[t]) {
          ++report.removed_faces;
          continue;
        }
        s.tris[out] = s.tris[t];
        s.tri_input[out++] = s.tri_input[t];
      }
      s.tris.resize(out);
      s.tri_input.resize(out);
      continue;
    }
    split_fans(s, glued, report);
    if (bad.empty()) break;
  }
  const uint32_t split = report.split_vertices - split_before;
  if (split > 0)
    report.issues.push_back(
        {InputIssue::Severity::repaired, "W102",
         fmt::format("split {} non-manifold vertices (one copy per fan)", split), split});
  if (report.removed_faces > 0)
    report.issues.push_back(
        {InputIssue::Severity::repaired, "W103",
         fmt::format("removed {} faces to make every edge manifold", report.removed_faces),
         report.removed_faces});
}

}  // namespace isoquad::prep
