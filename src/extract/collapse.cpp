#include "extract/collapse.hpp"

#include <algorithm>
#include <array>
#include <optional>

namespace isoquad {

namespace {

using Quad = std::array<uint32_t, 4>;
constexpr std::size_t kMaxValence = 6;

int corner_of(const Quad& q, uint32_t v) {
  for (int k = 0; k < 4; ++k)
    if (q[k] == v) return k;
  return -1;
}

struct Collapser {
  QuadMesh& qm;
  std::vector<char>& movable;
  double max_offset;
  std::vector<std::vector<uint32_t>> around;  // live quads at each vertex (pruned lazily)
  std::vector<char> quad_alive, vertex_alive, touched;

  Collapser(QuadMesh& m, std::vector<char>& mov, double offset)
      : qm(m),
        movable(mov),
        max_offset(offset),
        around(m.positions.size()),
        quad_alive(m.quads.size(), 1),
        vertex_alive(m.positions.size(), 1),
        touched(m.positions.size(), 0) {
    for (uint32_t f = 0; f < qm.quads.size(); ++f)
      for (const uint32_t v : qm.quads[f]) around[v].push_back(f);
  }

  std::vector<uint32_t> quads_at(uint32_t v) const {
    std::vector<uint32_t> out;
    for (const uint32_t f : around[v])
      if (quad_alive[f] && corner_of(qm.quads[f], v) >= 0) out.push_back(f);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }
  // Quads (other than `skip`) with the edge x-y, in `quads` (x's quads, edited or not).
  static uint32_t edge_faces(const std::vector<Quad>& quads, uint32_t x, uint32_t y) {
    uint32_t n = 0;
    for (const Quad& q : quads) {
      const int k = corner_of(q, x);
      if (k >= 0 && (q[(k + 1) % 4] == y || q[(k + 3) % 4] == y)) ++n;
    }
    return n;
  }
  static std::vector<uint32_t> neighbours(const std::vector<Quad>& quads, uint32_t v) {
    std::vector<uint32_t> out;
    for (const Quad& q : quads) {
      const int k = corner_of(q, v);
      if (k < 0) continue;
      out.push_back(q[(k + 1) % 4]);
      out.push_back(q[(k + 3) % 4]);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }
  // Interior: every edge at v has two quads.
  static bool interior(const std::vector<Quad>& quads, uint32_t v) {
    for (const uint32_t w : neighbours(quads, v))
      if (edge_faces(quads, v, w) != 2) return false;
    return true;
  }

  // Distance from x to the quads.
  double distance_to(const Vec3& x, const std::vector<Quad>& quads) const {
    double best = INFINITY;
    for (const Quad& q : quads) best = std::min(best, distance_to_quad(qm.positions, q, x));
    return best;
  }

  struct Edit {
    std::vector<std::pair<uint32_t, Quad>> rewrite;  // quad -> new corners
    std::vector<uint32_t> drop_quads, drop_vertices;
    uint32_t doublets = 0;
    uint32_t survivor = kInvalid;
  };

  // The edit that merges r into s across quad q, or nothing if it would break the mesh.
  std::optional<Edit> plan(uint32_t q, uint32_t s, uint32_t r) const {
    const Quad& quad = qm.quads[q];
    const int ks = corner_of(quad, s);
    const uint32_t b = quad[(ks + 1) % 4], d = quad[(ks + 3) % 4];
    const std::vector<uint32_t> fs = quads_at(s), fr = quads_at(r);
    // The ends share only q.
    for (const uint32_t f : fs)
      if (f != q && std::binary_search(fr.begin(), fr.end(), f)) return std::nullopt;
    auto corners = [&](const std::vector<uint32_t>& fl) {
      std::vector<Quad> out;
      for (const uint32_t f : fl) out.push_back(qm.quads[f]);
      return out;
    };
    const std::vector<Quad> qs = corners(fs), qr = corners(fr);
    // The ends share no neighbour but b and d (else two edges would become one twice).
    const std::vector<uint32_t> ns = neighbours(qs, s), nr = neighbours(qr, r);
    if (std::binary_search(ns.begin(), ns.end(), r)) return std::nullopt;
    for (const uint32_t w : ns)
      if (w != b && w != d && std::binary_search(nr.begin(), nr.end(), w)) return std::nullopt;
    // The merged corner keeps a valence of 6 at most: collapses stacking up at one vertex gave
    // the cow valences of 10, with 36-degree quad corners around them.
    if (ns.size() + nr.size() - 2 > kMaxValence) return std::nullopt;
    // Each merged edge keeps a quad: s-b and r-b are not both on the boundary.
    for (const uint32_t x : {b, d})
      if (edge_faces(qs, s, x) + edge_faces(qr, r, x) < 3) return std::nullopt;

    Edit edit;
    edit.survivor = s;
    edit.drop_quads.push_back(q);
    edit.drop_vertices.push_back(r);
    for (const uint32_t f : fr) {
      if (f == q) continue;
      Quad n = qm.quads[f];
      n[corner_of(n, r)] = s;
      edit.rewrite.push_back({f, n});
    }
    // The removed corner's surface point must stay close to the quads that replace it: a
    // collapse at a tip (a horn, a fin) would cut it off.
    {
      std::vector<Quad> fan;
      for (const auto& [g, n] : edit.rewrite) fan.push_back(n);
      if (distance_to(qm.positions[r], fan) > max_offset) return std::nullopt;
    }
    // The quads at b and d after the merge; a neighbour left inside with two is a doublet.
    auto after = [&](uint32_t f) {
      for (const auto& [g, n] : edit.rewrite)
        if (g == f) return n;
      return qm.quads[f];
    };
    for (const uint32_t x : {b, d}) {
      std::vector<uint32_t> fx;
      std::vector<Quad> qx;
      for (const uint32_t f : quads_at(x))
        if (f != q) fx.push_back(f), qx.push_back(after(f));
      if (qx.size() != 2 || !interior(qx, x)) continue;
      if (!movable[x]) return std::nullopt;
      // f1 = (x, u, y, z), f2 = (x, z, w, u) become (u, y, z, w).
      const Quad f1 = qx[0], f2 = qx[1];
      const int k1 = corner_of(f1, x), k2 = corner_of(f2, x);
      const uint32_t u = f1[(k1 + 1) % 4], y = f1[(k1 + 2) % 4], z = f1[(k1 + 3) % 4];
      if (f2[(k2 + 1) % 4] != z || f2[(k2 + 3) % 4] != u) return std::nullopt;
      const uint32_t w = f2[(k2 + 2) % 4];
      if (w == y || w == s || y == s || w == r || y == r) return std::nullopt;
      // u and z each lose a quad; neither may become a doublet in turn.
      for (const uint32_t t : {u, z}) {
        std::vector<Quad> qt;
        for (const uint32_t f : quads_at(t))
          if (f != q) qt.push_back(after(f));
        if (qt.size() <= 3 && interior(qt, t)) return std::nullopt;
      }
      const Quad merged = {u, y, z, w};
      if (distance_to(qm.positions[x], {merged}) > max_offset) return std::nullopt;
      bool replaced = false;
      for (auto& [g, n] : edit.rewrite)
        if (g == fx[0]) n = merged, replaced = true;
      if (!replaced) edit.rewrite.push_back({fx[0], merged});
      edit.rewrite.erase(std::remove_if(edit.rewrite.begin(), edit.rewrite.end(),
                                        [&](const auto& e) { return e.first == fx[1]; }),
                         edit.rewrite.end());
      edit.drop_quads.push_back(fx[1]);
      edit.drop_vertices.push_back(x);
      ++edit.doublets;
    }
    return edit;
  }

  void apply(const Edit& e) {
    for (const uint32_t f : e.drop_quads) quad_alive[f] = 0;
    for (const uint32_t v : e.drop_vertices) vertex_alive[v] = 0;
    for (const auto& [f, n] : e.rewrite) {
      qm.quads[f] = n;
      for (const uint32_t v : n) around[v].push_back(f);
    }
  }

  // Every vertex of every quad at a corner of q: what an edit at q may change.
  std::vector<uint32_t> reach(uint32_t q) const {
    std::vector<uint32_t> out;
    for (const uint32_t v : qm.quads[q])
      for (const uint32_t f : quads_at(v))
        for (const uint32_t w : qm.quads[f]) out.push_back(w);
    return out;
  }

  void compact() {
    std::vector<uint32_t> index(qm.positions.size(), kInvalid);
    uint32_t n = 0;
    for (uint32_t v = 0; v < index.size(); ++v)
      if (vertex_alive[v]) index[v] = n++;
    auto keep = [&](auto& data) {
      uint32_t out = 0;
      for (uint32_t v = 0; v < index.size(); ++v)
        if (index[v] != kInvalid) data[out++] = data[v];
      data.resize(n);
    };
    keep(qm.positions);
    keep(qm.surface);
    keep(qm.vertex_meta_vertex);
    keep(qm.vertex_meta_edge);
    keep(qm.placed);
    if (qm.mapped.size() == index.size()) keep(qm.mapped);
    keep(qm.merged);
    keep(movable);
    uint32_t out = 0;
    for (uint32_t f = 0; f < qm.quads.size(); ++f) {
      if (!quad_alive[f]) continue;
      Quad q = qm.quads[f];
      for (uint32_t& v : q) v = index[v];
      qm.quads[out] = q;
      qm.quad_patch[out] = qm.quad_patch[f];
      ++out;
    }
    qm.quads.resize(out);
    qm.quad_patch.resize(out);
  }
};

}  // namespace

void collapse_diagonals(QuadMesh& qm, std::vector<char>& movable,
                        const std::vector<CollapseRequest>& requests, double max_offset,
                        CollapseReport& report) {
  qm.merged.resize(qm.positions.size(), 0);
  Collapser c(qm, movable, max_offset);
  for (const CollapseRequest& req : requests) {
    const std::vector<uint32_t> near = c.reach(req.quad);
    if (std::any_of(near.begin(), near.end(), [&](uint32_t v) { return c.touched[v]; })) continue;
    const Quad quad = qm.quads[req.quad];
    std::optional<Collapser::Edit> edit;
    for (const int k : {req.worst, (req.worst + 1) % 4}) {  // through the worst corner, then not
      const uint32_t a = quad[k], o = quad[(k + 2) % 4];
      // The worst corner goes if it may; else it stays and the opposite one comes to it.
      if (movable[a]) edit = c.plan(req.quad, o, a);
      if (!edit && movable[o]) edit = c.plan(req.quad, a, o);
      if (edit) break;
    }
    if (!edit) {
      ++report.refused;
      continue;
    }
    c.apply(*edit);
    qm.merged[edit->survivor] = 1;
    for (const uint32_t v : near) c.touched[v] = 1;
    ++report.collapsed;
    report.doublets += edit->doublets;
  }
  c.compact();
}

}  // namespace isoquad
