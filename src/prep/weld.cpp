#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "core/union_find.hpp"
#include "prep/steps.hpp"

namespace isoquad::prep {

namespace {

// Vertices on an edge that only one face uses: where split seams and STL soups have cracks.
std::vector<char> boundary_vertices(const PolyMesh& soup) {
  std::vector<std::pair<uint64_t, uint32_t>> edges;
  for (std::size_t f = 0; f < soup.num_faces(); ++f) {
    const auto face = soup.face(f);
    for (std::size_t i = 0; i < face.size(); ++i) {
      const uint32_t a = face[i], b = face[(i + 1) % face.size()];
      edges.push_back({(uint64_t(std::min(a, b)) << 32) | std::max(a, b), 0});
    }
  }
  std::sort(edges.begin(), edges.end());
  std::vector<char> on_boundary(soup.num_vertices(), 0);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    if (j - i == 1) {
      on_boundary[edges[i].first >> 32] = 1;
      on_boundary[edges[i].first & 0xFFFFFFFFu] = 1;
    }
    i = j;
  }
  return on_boundary;
}

}  // namespace

std::vector<uint32_t> weld_map(const PolyMesh& soup, bool all, double eps, uint32_t& welded) {
  const uint32_t n = uint32_t(soup.num_vertices());
  std::vector<uint32_t> candidates;
  const std::vector<char> boundary = all ? std::vector<char>() : boundary_vertices(soup);
  for (uint32_t v = 0; v < n; ++v)
    if (all || boundary[v]) candidates.push_back(v);

  UnionFind uf(n);
  const auto& P = soup.positions;
  // Exact duplicates first, by sorting: all a zero eps welds, and with eps > 0 the grid below
  // then sees one vertex per position (an STL soup has each about six times; a heap of copies
  // at one point made it quadratic).
  {
    auto less = [&](uint32_t a, uint32_t b) {
      if (P[a].x != P[b].x) return P[a].x < P[b].x;
      if (P[a].y != P[b].y) return P[a].y < P[b].y;
      if (P[a].z != P[b].z) return P[a].z < P[b].z;
      return a < b;
    };
    std::sort(candidates.begin(), candidates.end(), less);
    for (std::size_t i = 1; i < candidates.size(); ++i)
      if (P[candidates[i]] == P[candidates[i - 1]]) uf.unite(candidates[i], candidates[i - 1]);
  }
  if (eps > 0) {
    std::erase_if(candidates, [&](uint32_t v) { return uf.find(v) != v; });
    // Spatial hash with cells of size eps; neighbours within eps are in the 27 adjacent cells.
    // Cells are numbered from the candidates' lower corner and are at least 2^-40 of their
    // extent, so numbers stay below 2^40: a tiny eps (--weld-eps 1e-30) numbered them past
    // int64 (undefined), and clamping the numbers would put every vertex in one cell.
    Box3 box;
    for (uint32_t v : candidates) box.add(P[v]);
    const double size = std::max(eps, std::ldexp(box.diagonal(), -40));
    auto cell = [&](Vec3 p) {
      const Vec3 q = (p - box.lo) / size;
      return std::array<int64_t, 3>{int64_t(q.x), int64_t(q.y), int64_t(q.z)};
    };
    auto key = [](const std::array<int64_t, 3>& c) {
      return uint64_t(c[0]) * 73856093u ^ uint64_t(c[1]) * 19349663u ^ uint64_t(c[2]) * 83492791u;
    };
    std::unordered_map<uint64_t, std::vector<uint32_t>> grid;
    for (uint32_t v : candidates) grid[key(cell(P[v]))].push_back(v);
    for (uint32_t v : candidates) {
      const auto c = cell(P[v]);
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            const auto it = grid.find(key({c[0] + dx, c[1] + dy, c[2] + dz}));
            if (it == grid.end()) continue;
            for (uint32_t w : it->second)
              if (w < v && norm(P[w] - P[v]) <= eps) uf.unite(v, w);
          }
    }
  }
  std::vector<uint32_t> rep(n);
  welded = 0;
  for (uint32_t v = 0; v < n; ++v) {
    rep[v] = uf.find(v);
    if (rep[v] != v) ++welded;
  }
  return rep;
}

WeldTopology weld_topology(const PolyMesh& soup, const std::vector<uint32_t>& weld) {
  std::vector<uint64_t> edges;
  std::vector<char> used(soup.num_vertices(), 0);
  int64_t faces = 0;
  for (std::size_t f = 0; f < soup.num_faces(); ++f) {
    std::vector<uint32_t> vs;
    for (const uint32_t v : soup.face(f))
      if (std::find(vs.begin(), vs.end(), weld[v]) == vs.end()) vs.push_back(weld[v]);
    if (vs.size() < 3) continue;  // collapses: dropped (W105)
    ++faces;
    for (std::size_t i = 0; i < vs.size(); ++i) {
      const uint32_t a = vs[i], b = vs[(i + 1) % vs.size()];
      used[a] = 1;
      edges.push_back((uint64_t(std::min(a, b)) << 32) | std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  UnionFind loops(soup.num_vertices());
  std::vector<char> on_boundary(soup.num_vertices(), 0);
  int64_t distinct = 0;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    ++distinct;
    if (j - i == 1) {
      const uint32_t a = uint32_t(edges[i] >> 32), b = uint32_t(edges[i] & 0xFFFFFFFFu);
      loops.unite(a, b);
      on_boundary[a] = on_boundary[b] = 1;
    }
    i = j;
  }
  WeldTopology t;
  t.euler = int64_t(std::count(used.begin(), used.end(), 1)) - distinct + faces;
  for (uint32_t v = 0; v < soup.num_vertices(); ++v)
    if (on_boundary[v] && loops.find(v) == v) ++t.boundary_loops;
  return t;
}

}  // namespace isoquad::prep
