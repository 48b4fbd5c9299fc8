#include "layout/meta_mesh.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "isoquad/error.hpp"
#include "seg/patch_topology.hpp"

namespace isoquad {

namespace {

constexpr double kPi = std::numbers::pi;

// Corners of the mesh boundary: the turning (pi minus the mesh angle) summed over a window of
// arc length on each side must exceed the limit, and the vertex must turn most within it. A
// single vertex test would fire all along a jagged (sawtooth) boundary.
std::vector<char> boundary_corners(const TriMesh& m, const MetaMeshOptions& o) {
  std::vector<char> corner(m.num_vertices(), 0);
  const FaceData<uint32_t> no_labels(m.num_faces(), 0);
  const double limit = o.boundary_corner_deg * kPi / 180;
  for (const auto& loop : m.boundary_loops()) {
    const std::size_t n = loop.size();
    std::vector<double> turn(n), s(n + 1, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      turn[i] = kPi - patch_angle(m, no_labels, m.from(loop[i]), kInvalid);
      s[i + 1] = s[i] + norm(m.position(m.to(loop[i])) - m.position(m.from(loop[i])));
    }
    const double window = o.corner_window > 0 ? o.corner_window : 3.0 * s[n] / double(n);
    for (std::size_t i = 0; i < n; ++i) {
      double sum = turn[i];
      bool is_max = true;
      for (int dir : {-1, 1})
        for (std::size_t k = 1; k < n; ++k) {
          const std::size_t j = dir > 0 ? (i + k) % n : (i + n - k % n) % n;
          const double d = std::fabs(s[i] - s[j]);
          if (std::min(d, s[n] - d) > window) break;
          sum += turn[j];
          const double a = std::fabs(turn[j]), b = std::fabs(turn[i]);
          if (a > b || (a == b && j < i)) is_max = false;
        }
      corner[m.from(loop[i])] = is_max && std::fabs(sum) > limit;
    }
  }
  return corner;
}

std::vector<char> meta_vertex_flags(const TriMesh& m, const FaceData<uint32_t>& labels,
                                    const std::vector<char>& corners,
                                    const std::vector<char>& inserted) {
  std::vector<char> meta(m.num_vertices(), 0);
  for (uint32_t v = 0; v < m.num_vertices(); ++v) {
    meta[v] = wedge_count(m, labels, v) >= (m.is_boundary_vertex(v) ? 2u : 3u) || corners[v] ||
              inserted[v];
  }
  return meta;
}

// One boundary cycle per patch (each is a disk), as halfedges with the patch on the left.
std::vector<std::vector<uint32_t>> patch_cycles(const TriMesh& m, const FaceData<uint32_t>& labels,
                                                uint32_t n) {
  std::vector<std::vector<uint32_t>> cycles(n);
  std::vector<char> visited(m.num_halfedges(), 0);
  for (uint32_t h0 = 0; h0 < m.num_halfedges(); ++h0) {
    if (visited[h0] || !is_patch_boundary(m, labels, h0)) continue;
    auto& c = cycles[labels[TriMesh::face_of(h0)]];
    if (!c.empty())
      throw Error(ErrorKind::internal, "E700",
                  fmt::format("patch {} has two boundary loops (not a disk)",
                              labels[TriMesh::face_of(h0)]));
    for (uint32_t h = h0; !visited[h]; h = next_patch_boundary_halfedge(m, labels, h)) {
      visited[h] = 1;
      c.push_back(h);
    }
  }
  return cycles;
}

double edge_length(const TriMesh& m, uint32_t h) {
  return norm(m.position(m.to(h)) - m.position(m.from(h)));
}

// Picks meta-vertices for a patch whose boundary has none: the 4 vertices that turn most (the
// corners of a plate), at least a perimeter/8 apart; arc-length quarters where nothing turns.
void insert_four(const TriMesh& m, const FaceData<uint32_t>& labels,
                 const std::vector<uint32_t>& cycle, std::vector<char>& inserted, uint32_t count) {
  const uint32_t p = labels[TriMesh::face_of(cycle[0])];
  std::vector<double> s(cycle.size() + 1, 0.0);
  for (std::size_t i = 0; i < cycle.size(); ++i) s[i + 1] = s[i] + edge_length(m, cycle[i]);
  const double perimeter = s.back();
  auto gap = [&](std::size_t i, std::size_t j) {
    const double d = std::fabs(s[i] - s[j]);
    return std::min(d, perimeter - d);
  };
  std::vector<std::size_t> order(cycle.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::vector<double> turn(cycle.size());
  for (std::size_t i = 0; i < cycle.size(); ++i)
    turn[i] = std::fabs(kPi - patch_angle(m, labels, m.from(cycle[i]), p));
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return turn[a] > turn[b]; });
  std::vector<std::size_t> chosen;
  for (std::size_t i : order) {
    if (chosen.size() == count || turn[i] < kPi / 8) break;
    if (std::all_of(chosen.begin(), chosen.end(),
                    [&](std::size_t j) { return gap(i, j) >= perimeter / 8; }))
      chosen.push_back(i);
  }
  // Fill up at the arc-length positions farthest from what is chosen.
  while (chosen.size() < count && chosen.size() < cycle.size()) {
    std::size_t best = 0;
    double best_gap = -1;
    for (std::size_t i = 0; i < cycle.size(); ++i) {
      double g = perimeter;
      for (std::size_t j : chosen) g = std::min(g, gap(i, j));
      if (g > best_gap) best_gap = g, best = i;
    }
    chosen.push_back(best);
  }
  for (std::size_t i : chosen) inserted[m.from(cycle[i])] = 1;
}

// Splits the longest stretches between meta-vertices at their arc-length midpoints. A stretch
// shared with a patch that has 4 meta-vertices or more (or with the mesh boundary) is preferred:
// that patch can take the new point as a 180-degree side point, whereas between two 4-sided
// patches it would be a corner on both sides, a valence-2 vertex.
void insert_on_items(const TriMesh& m, const FaceData<uint32_t>& labels,
                     const std::vector<uint32_t>& cycle, const std::vector<char>& meta,
                     const std::vector<uint32_t>& meta_count, std::vector<char>& inserted,
                     uint32_t count) {
  std::vector<char> is_meta(cycle.size());
  for (std::size_t i = 0; i < cycle.size(); ++i)
    is_meta[i] = meta[m.from(cycle[i])] || inserted[m.from(cycle[i])];
  for (uint32_t k = 0; k < count; ++k) {
    // The longest stretch that has a vertex inside.
    double best_len = -1;
    std::size_t best_start = 0, best_mid = 0;
    const std::size_t first =
        std::size_t(std::find(is_meta.begin(), is_meta.end(), 1) - is_meta.begin());
    for (std::size_t a = first, steps = 0; steps < cycle.size();) {
      std::size_t b = (a + 1) % cycle.size();
      double len = edge_length(m, cycle[a]);
      std::size_t n = 1;
      while (!is_meta[b]) len += edge_length(m, cycle[b]), b = (b + 1) % cycle.size(), ++n;
      const uint32_t t = m.twin(cycle[a]);
      const bool roomy = t == kInvalid || meta_count[labels[TriMesh::face_of(t)]] >= 4;
      const double score = roomy ? len : 0.25 * len;
      if (n >= 2 && score > best_len) {
        best_len = score, best_start = a;
        double acc = 0;
        std::size_t i = a;
        while (acc + edge_length(m, cycle[i]) < len / 2)
          acc += edge_length(m, cycle[i]), i = (i + 1) % cycle.size();
        i = (i + 1) % cycle.size();  // vertex after the midpoint edge
        if (is_meta[i]) i = (i + cycle.size() - 1) % cycle.size();
        best_mid = i;
      }
      steps += n;
      a = b;
    }
    if (best_len < 0 || best_mid == best_start) return;  // no stretch has an interior vertex
    is_meta[best_mid] = 1;
    inserted[m.from(cycle[best_mid])] = 1;
  }
}

}  // namespace

MetaMesh build_meta_mesh(const TriMesh& m, const FaceData<uint32_t>& labels, uint32_t n,
                         const EdgeData<char>& feature, const MetaMeshOptions& o) {
  std::vector<char> inserted(m.num_vertices(), 0);
  for (uint32_t v : o.forced) inserted[v] = 1;
  const std::vector<char> corners = boundary_corners(m, o);
  std::vector<char> meta;
  std::vector<std::vector<uint32_t>> cycles = patch_cycles(m, labels, n);
  uint32_t inserted_count = 0;
  for (int round = 0;; ++round) {
    meta = meta_vertex_flags(m, labels, corners, inserted);
    std::vector<uint32_t> meta_count(n, 0);
    for (uint32_t p = 0; p < n; ++p)
      for (uint32_t h : cycles[p]) meta_count[p] += meta[m.from(h)];
    bool changed = false;
    for (uint32_t p = 0; p < n; ++p) {
      uint32_t mp = 0;
      for (uint32_t h : cycles[p]) mp += meta[m.from(h)];
      if (mp >= o.min_corners) continue;
      const uint32_t before = uint32_t(std::count(inserted.begin(), inserted.end(), 1));
      if (mp == 0)
        insert_four(m, labels, cycles[p], inserted, o.min_corners);
      else
        insert_on_items(m, labels, cycles[p], meta, meta_count, inserted, o.min_corners - mp);
      const uint32_t added = uint32_t(std::count(inserted.begin(), inserted.end(), 1)) - before;
      if (added + mp < o.min_corners || round > 8)
        throw Error(
            ErrorKind::layout, "E301",
            fmt::format(
                "patch {} has {} meta-vertices and its boundary ({} edges) cannot take {} more", p,
                mp, cycles[p].size(), o.min_corners - mp));
      inserted_count += added;
      changed = true;
      meta = meta_vertex_flags(m, labels, corners, inserted);
    }
    if (!changed) break;
  }

  MetaMesh mm;
  mm.inserted = inserted_count;
  for (uint32_t v = 0; v < m.num_vertices(); ++v)
    if (inserted[v]) mm.inserted_vertices.push_back(v);
  mm.vertex_meta_vertex = VertexData<uint32_t>(m.num_vertices(), kInvalid);
  mm.vertex_meta_edge = VertexData<uint32_t>(m.num_vertices(), kInvalid);
  for (uint32_t v = 0; v < m.num_vertices(); ++v) {
    if (!meta[v]) continue;
    mm.vertex_meta_vertex[v] = uint32_t(mm.vertices.size());
    MetaVertex mv;
    mv.vertex = v;
    mv.on_boundary = m.is_boundary_vertex(v);
    mv.inserted = inserted[v] && wedges_at(m, labels, v).size() < (mv.on_boundary ? 2u : 3u);
    for (const Wedge& w : wedges_at(m, labels, v)) mv.wedge_patches.push_back(w.patch);
    mm.vertices.push_back(std::move(mv));
  }

  std::vector<uint32_t> halfedge_edge(m.num_halfedges(), kInvalid);
  mm.faces.resize(n);
  for (uint32_t p = 0; p < n; ++p) {
    std::vector<uint32_t> c = cycles[p];
    const auto first =
        std::find_if(c.begin(), c.end(), [&](uint32_t h) { return meta[m.from(h)] != 0; });
    std::rotate(c.begin(), first, c.end());
    mm.faces[p].patch = p;
    for (std::size_t i = 0; i < c.size();) {
      std::size_t j = i + 1;
      while (j < c.size() && !meta[m.from(c[j])]) ++j;
      const uint32_t t = m.twin(c[i]);
      if (t != kInvalid && halfedge_edge[t] != kInvalid) {
        mm.faces[p].cycle.push_back({halfedge_edge[t], false});
      } else {
        const uint32_t id = uint32_t(mm.edges.size());
        MetaEdge e;
        e.left = p;
        e.right = t == kInvalid ? kInvalid : labels[TriMesh::face_of(t)];
        e.feature = true;
        for (std::size_t k = i; k < j; ++k) {
          e.halfedges.push_back(c[k]);
          e.vertices.push_back(m.from(c[k]));
          e.length += edge_length(m, c[k]);
          e.feature = e.feature && feature[m.edge(c[k])];
          halfedge_edge[c[k]] = id;
        }
        e.vertices.push_back(m.to(c[j - 1]));
        e.mv0 = mm.vertex_meta_vertex[e.vertices.front()];
        e.mv1 = mm.vertex_meta_vertex[e.vertices.back()];
        for (std::size_t k = 1; k + 1 < e.vertices.size(); ++k)
          mm.vertex_meta_edge[e.vertices[k]] = id;
        mm.edges.push_back(std::move(e));
        mm.faces[p].cycle.push_back({id, true});
      }
      i = j;
    }
  }
  return mm;
}

void check_meta_mesh(const TriMesh& m, const FaceData<uint32_t>& labels, const MetaMesh& mm) {
  auto fail = [](const std::string& what) {
    throw Error(ErrorKind::internal, "E700", "meta-mesh invariant: " + what);
  };
  std::vector<uint32_t> uses(mm.edges.size(), 0);
  for (uint32_t e = 0; e < mm.edges.size(); ++e) {
    const MetaEdge& me = mm.edges[e];
    if (me.left == me.right)
      fail(fmt::format("meta-edge {} separates patch {} from itself", e, me.left));
    if (me.mv0 == kInvalid || me.mv1 == kInvalid || me.mv0 == me.mv1)
      fail(fmt::format("meta-edge {} does not join two distinct meta-vertices", e));
    std::vector<uint32_t> sorted = me.vertices;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
      fail(fmt::format("meta-edge {} is not a simple path", e));
    for (std::size_t k = 0; k < me.halfedges.size(); ++k) {
      const uint32_t h = me.halfedges[k];
      if (m.from(h) != me.vertices[k] || m.to(h) != me.vertices[k + 1] ||
          labels[TriMesh::face_of(h)] != me.left)
        fail(fmt::format("meta-edge {} halfedge {} does not follow its path", e, k));
      const uint32_t t = m.twin(h);
      if ((t == kInvalid) != (me.right == kInvalid) ||
          (t != kInvalid && labels[TriMesh::face_of(t)] != me.right))
        fail(fmt::format("meta-edge {} changes its right patch along the way", e));
    }
  }
  for (const MetaFace& f : mm.faces) {
    if (f.cycle.size() < 3)
      fail(fmt::format("patch {} has {} meta-edges", f.patch, f.cycle.size()));
    for (std::size_t i = 0; i < f.cycle.size(); ++i) {
      const BoundaryItem& it = f.cycle[i];
      const MetaEdge& e = mm.edges[it.edge];
      ++uses[it.edge];
      if ((it.forward ? e.left : e.right) != f.patch)
        fail(fmt::format("patch {} lists a meta-edge it does not bound", f.patch));
      const uint32_t end = it.forward ? e.mv1 : e.mv0;
      if (end != f.start_vertex((i + 1) % f.cycle.size(), mm.edges))
        fail(fmt::format("the cycle of patch {} is not closed at item {}", f.patch, i));
    }
  }
  for (uint32_t e = 0; e < mm.edges.size(); ++e)
    if (uses[e] != (mm.edges[e].right == kInvalid ? 1u : 2u))
      fail(fmt::format("meta-edge {} is used {} times", e, uses[e]));
  if (mm.euler() != m.euler_characteristic())
    fail(fmt::format("euler characteristic {} differs from the mesh's {}", mm.euler(),
                     m.euler_characteristic()));
}

}  // namespace isoquad
