#include <algorithm>
#include <numeric>

#include "core/edge_groups.hpp"
#include "prep/steps.hpp"

namespace isoquad::prep {

namespace {
struct Neighbour {
  uint32_t tri;
  bool same_direction;  // both faces run along the edge the same way: one must be flipped
  uint32_t lo, hi;
};
}  // namespace

std::vector<SoupComponent> orient_components(Soup& s, InputReport& report) {
  const uint32_t nt = uint32_t(s.tris.size());
  std::vector<std::vector<Neighbour>> adj(nt);
  std::vector<char> has_boundary(nt, 0);
  for_each_edge_group(halfedges_by_edge(s.tris), [&](std::span<const EdgeHalfedge> g) {
    if (g.size() == 1) has_boundary[g[0].h / 3] = 1;
    if (g.size() != 2) return;
    const bool same = s.tris[g[0].h / 3][g[0].h % 3] == s.tris[g[1].h / 3][g[1].h % 3];
    adj[g[0].h / 3].push_back({g[1].h / 3, same, g[0].lo, g[0].hi});
    adj[g[1].h / 3].push_back({g[0].h / 3, same, g[0].lo, g[0].hi});
  });

  std::vector<SoupComponent> comps;
  std::vector<uint32_t> comp_of(nt, kInvalid);
  std::vector<char> flip(nt, 0);
  std::vector<uint32_t> queue;
  for (uint32_t seed = 0; seed < nt; ++seed) {
    if (comp_of[seed] != kInvalid) continue;
    SoupComponent c;
    comp_of[seed] = uint32_t(comps.size());
    queue.assign(1, seed);
    for (std::size_t qi = 0; qi < queue.size(); ++qi) {  // BFS keeps the result deterministic
      const uint32_t t = queue[qi];
      c.tris.push_back(t);
      for (const Neighbour& n : adj[t]) {
        const char want = char(flip[t] ^ n.same_direction);
        if (comp_of[n.tri] == kInvalid) {
          comp_of[n.tri] = comp_of[seed];
          flip[n.tri] = want;
          queue.push_back(n.tri);
        } else if (flip[n.tri] != want && c.orientable) {
          c.orientable = false;
          c.conflict_a = s.vertex_input[n.lo];
          c.conflict_b = s.vertex_input[n.hi];
        }
      }
    }
    if (c.orientable) {
      const bool closed =
          std::none_of(c.tris.begin(), c.tris.end(), [&](uint32_t t) { return has_boundary[t]; });
      bool flip_all;
      if (closed) {  // outward: positive signed volume once the flips are applied
        double volume = 0;
        for (uint32_t t : c.tris) {
          const Tri& f = s.tris[t];
          const double v = dot(s.positions[f[0]], cross(s.positions[f[1]], s.positions[f[2]]));
          volume += flip[t] ? -v : v;
        }
        flip_all = volume < 0;
      } else {  // keep the orientation most input faces already have
        const auto flipped =
            std::count_if(c.tris.begin(), c.tris.end(), [&](uint32_t t) { return flip[t]; });
        flip_all = 2 * std::size_t(flipped) > c.tris.size();
      }
      for (uint32_t t : c.tris) {
        if (bool(flip[t]) != flip_all) {
          std::swap(s.tris[t][1], s.tris[t][2]);
          ++report.flipped_faces;
        }
      }
    }
    std::sort(c.tris.begin(), c.tris.end());
    comps.push_back(std::move(c));
  }
  return comps;
}

ComponentReport combinatorial_topology(const Soup& s, const std::vector<uint32_t>& tris) {
  ComponentReport r;
  std::vector<Tri> local;
  local.reserve(tris.size());
  for (uint32_t t : tris) local.push_back(s.tris[t]);
  std::vector<uint32_t> verts;
  for (const Tri& t : local) verts.insert(verts.end(), t.begin(), t.end());
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  // Boundary loops: after make_manifold every boundary vertex has exactly two boundary edges,
  // so the loops are the connected components of the boundary edges.
  std::vector<uint32_t> parent(verts.size());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  auto local_id = [&](uint32_t v) {
    return uint32_t(std::lower_bound(verts.begin(), verts.end(), v) - verts.begin());
  };
  std::vector<char> on_boundary(verts.size(), 0);
  for_each_edge_group(halfedges_by_edge(local), [&](std::span<const EdgeHalfedge> g) {
    ++r.edges;
    if (g.size() != 1) return;
    const uint32_t a = local_id(g[0].lo), b = local_id(g[0].hi);
    on_boundary[a] = on_boundary[b] = 1;
    parent[find(a)] = find(b);
  });
  for (uint32_t v = 0; v < verts.size(); ++v)
    if (on_boundary[v] && find(v) == v) ++r.boundary_loops;
  r.vertices = uint32_t(verts.size());
  r.faces = uint32_t(tris.size());
  r.euler = int64_t(r.vertices) - int64_t(r.edges) + int64_t(r.faces);
  return r;
}

}  // namespace isoquad::prep
