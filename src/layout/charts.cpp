#include "layout/charts.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <set>

#include "isoquad/error.hpp"
#include "seg/patch_topology.hpp"

namespace isoquad {

namespace {

[[noreturn]] void fail(const std::string& what) {
  throw Error(ErrorKind::internal, "E700", "layout invariant: " + what);
}

constexpr Lattice kDirection[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};

// Where meta-edge e starts and ends in patch p's chart, in the edge's own direction mv0 -> mv1.
std::pair<Lattice, Lattice> edge_in_chart(const MetaMesh& meta, const Chart& chart, uint32_t p,
                                          uint32_t e) {
  const MetaFace& f = meta.faces[p];
  for (uint32_t i = 0; i < f.cycle.size(); ++i) {
    if (f.cycle[i].edge != e) continue;
    const Lattice a = chart.item_position[i], b = chart.item_position[(i + 1) % f.cycle.size()];
    return f.cycle[i].forward ? std::pair{a, b} : std::pair{b, a};
  }
  fail(fmt::format("meta-edge {} is not on patch {}", e, p));
}

}  // namespace

int64_t Layout::quads() const {
  int64_t q = 0;
  for (const Chart& c : charts) q += c.width * c.height;
  return q;
}

void build_charts(const MetaMesh& meta, const std::vector<std::vector<uint8_t>>& sides,
                  Layout& layout) {
  const uint32_t n = uint32_t(meta.faces.size());
  layout.charts.assign(n, {});
  for (uint32_t p = 0; p < n; ++p) {
    const MetaFace& f = meta.faces[p];
    Chart& c = layout.charts[p];
    const uint32_t m = uint32_t(f.cycle.size());
    c.item_side = sides[p];
    c.item_position.assign(m, {0, 0});
    // Start at corner 0: the item that begins side 0.
    uint32_t start = 0;
    while (!(c.item_side[start] == 0 && c.item_side[(start + m - 1) % m] == 3)) ++start;
    for (uint32_t k = 0; k < 4; ++k) c.corners[k] = kInvalid;
    Lattice pos{0, 0};
    for (uint32_t s = 0; s < m; ++s) {
      const uint32_t i = (start + s) % m;
      c.item_position[i] = pos;
      if (s == 0 || c.item_side[i] != c.item_side[(i + m - 1) % m]) c.corners[c.item_side[i]] = i;
      const int64_t x = layout.length[f.cycle[i].edge];
      pos = {pos[0] + x * kDirection[c.item_side[i]][0],
             pos[1] + x * kDirection[c.item_side[i]][1]};
      if (c.item_side[i] == 0) c.width += x;
      if (c.item_side[i] == 1) c.height += x;
    }
    if (pos != Lattice{0, 0})
      fail(fmt::format("the walk around patch {} does not close ({}, {})", p, pos[0], pos[1]));
  }
  layout.transition.assign(meta.edges.size(), {});
  for (uint32_t e = 0; e < meta.edges.size(); ++e) {
    const MetaEdge& me = meta.edges[e];
    if (me.right == kInvalid) continue;
    const auto [ap, bp] = edge_in_chart(meta, layout.charts[me.left], me.left, e);
    const auto [aq, bq] = edge_in_chart(meta, layout.charts[me.right], me.right, e);
    const int64_t x = layout.length[e];
    const Lattice dp{(bp[0] - ap[0]) / x, (bp[1] - ap[1]) / x},
        dq{(bq[0] - aq[0]) / x, (bq[1] - aq[1]) / x};
    int k = 0;
    while (k < 4 && rotate(dp, k) != dq) ++k;
    if (k == 4) fail(fmt::format("meta-edge {}: no quarter turn maps its direction", e));
    const Lattice r = rotate(ap, k);
    layout.transition[e] = {k, {aq[0] - r[0], aq[1] - r[1]}};
  }
}

void check_layout(const TriMesh& mesh, const FaceData<uint32_t>& labels, const MetaMesh& meta,
                  const Layout& layout) {
  for (uint32_t e = 0; e < meta.edges.size(); ++e) {
    const MetaEdge& me = meta.edges[e];
    if (layout.length[e] < 1) fail(fmt::format("meta-edge {} has length {}", e, layout.length[e]));
    if (me.right == kInvalid) continue;
    const auto [ap, bp] = edge_in_chart(meta, layout.charts[me.left], me.left, e);
    const auto [aq, bq] = edge_in_chart(meta, layout.charts[me.right], me.right, e);
    const Transition& t = layout.transition[e];
    if (t.apply(ap) != aq || t.apply(bp) != bq)
      fail(fmt::format("transition of meta-edge {} misses an endpoint", e));
  }
  for (uint32_t p = 0; p < layout.charts.size(); ++p) {
    const Chart& c = layout.charts[p];
    std::set<Lattice> seen(c.item_position.begin(), c.item_position.end());
    if (seen.size() != c.item_position.size())
      fail(fmt::format("patch {} puts two meta-vertices on one lattice point", p));
    if (c.width < 1 || c.height < 1) fail(fmt::format("patch {} is {} x {}", p, c.width, c.height));
  }
  // Holonomy: compose the transitions around each interior meta-vertex, through its wedges CCW.
  std::vector<uint32_t> halfedge_edge(mesh.num_halfedges(), kInvalid);
  for (uint32_t e = 0; e < meta.edges.size(); ++e)
    for (uint32_t h : meta.edges[e].halfedges) {
      halfedge_edge[h] = e;
      if (mesh.twin(h) != kInvalid) halfedge_edge[mesh.twin(h)] = e;
    }
  int64_t identity = 0;
  for (uint32_t v = 0; v < meta.vertices.size(); ++v) {
    const MetaVertex& mv = meta.vertices[v];
    const int a = layout.quarter_turns[v];
    identity += mv.on_boundary ? 2 - a : 4 - a;
    if (mv.on_boundary) continue;
    Transition total;
    uint32_t first_patch = kInvalid, prev_patch = kInvalid;
    mesh.for_each_outgoing(mv.vertex, [&](uint32_t h) {
      const uint32_t p = labels[TriMesh::face_of(h)];
      if (first_patch == kInvalid) first_patch = prev_patch = p;
      if (p == prev_patch) return;
      const uint32_t e = halfedge_edge[h];
      const Transition step =
          meta.edges[e].left == prev_patch ? layout.transition[e] : layout.transition[e].inverse();
      total = step * total;
      prev_patch = p;
    });
    // Close the loop back into the first patch.
    const uint32_t h0 = mesh.outgoing(mv.vertex);
    const uint32_t e0 = halfedge_edge[h0];
    if (prev_patch != first_patch) {
      const Transition step = meta.edges[e0].left == prev_patch ? layout.transition[e0]
                                                                : layout.transition[e0].inverse();
      total = step * total;
    }
    // Position of the meta-vertex in the first patch's chart.
    const MetaFace& f = meta.faces[first_patch];
    Lattice pos{0, 0};
    for (uint32_t i = 0; i < f.cycle.size(); ++i)
      if (f.start_vertex(i, meta.edges) == v) pos = layout.charts[first_patch].item_position[i];
    if (total.apply(pos) != pos)
      fail(fmt::format("holonomy around meta-vertex {} does not fix it", v));
    if ((total.k - (4 - a) % 4 + 8) % 4 != 0 && (total.k - (a - 4) % 4 + 8) % 4 != 0)
      fail(fmt::format("holonomy around meta-vertex {} turns {} quarter turns for a_v = {}", v,
                       total.k, a));
  }
  if (identity != 4 * meta.euler())
    fail(fmt::format("quarter-turn identity: {} != 4 chi = {}", identity, 4 * meta.euler()));
}

}  // namespace isoquad
