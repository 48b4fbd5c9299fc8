// Groups the halfedges of a triangle list by undirected edge: the one way the code base finds
// which faces share an edge in a soup (before a TriMesh exists) and pairs twins.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace isoquad {

struct EdgeHalfedge {
  uint32_t lo, hi;  // the edge's endpoints, lo < hi
  uint32_t h;       // halfedge 3t + i, from corner i to corner (i+1)%3 of triangle t
};

// Sorted by (lo, hi, h): halfedges of one edge are adjacent, in triangle order. A counting sort
// by lo (visiting halfedges in order, so each bucket is in h order), then each bucket (a few
// entries: the edges whose smaller end is that vertex) by hi, stably. Four of these ran in the
// preparation of every mesh, and one per TriMesh built; std::sort of packed 64-bit keys took
// about 30% of bunny00's preparation.
inline std::vector<EdgeHalfedge> halfedges_by_edge(std::span<const std::array<uint32_t, 3>> tris) {
  const std::size_t n = 3 * tris.size();
  uint32_t nv = 0;
  for (const auto& t : tris) nv = std::max({nv, t[0] + 1, t[1] + 1, t[2] + 1});
  std::vector<uint32_t> start(std::size_t(nv) + 1, 0);
  auto ends = [&](std::size_t h) {
    const uint32_t a = tris[h / 3][h % 3], b = tris[h / 3][(h % 3 + 1) % 3];
    return std::pair(std::min(a, b), std::max(a, b));
  };
  for (std::size_t h = 0; h < n; ++h) ++start[ends(h).first + 1];
  for (uint32_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<EdgeHalfedge> keys(n);
  std::vector<uint32_t> next(start.begin(), start.end() - 1);
  for (std::size_t h = 0; h < n; ++h) {
    const auto [lo, hi] = ends(h);
    keys[next[lo]++] = {lo, hi, uint32_t(h)};
  }
  auto by_hi = [](const EdgeHalfedge& x, const EdgeHalfedge& y) { return x.hi < y.hi; };
  for (uint32_t v = 0; v < nv; ++v) {
    EdgeHalfedge* first = keys.data() + start[v];
    EdgeHalfedge* last = keys.data() + start[v + 1];
    if (last - first <= 16) {  // insertion sort, stable
      for (EdgeHalfedge* i = first + 1; i < last; ++i)
        for (EdgeHalfedge* j = i; j > first && by_hi(*j, *(j - 1)); --j) std::swap(*j, *(j - 1));
    } else {
      std::stable_sort(first, last, by_hi);
    }
  }
  return keys;
}

// Calls fn(span of the halfedges of one edge) for every edge.
template <class Fn>
void for_each_edge_group(const std::vector<EdgeHalfedge>& keys, Fn&& fn) {
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i + 1;
    while (j < keys.size() && keys[j].lo == keys[i].lo && keys[j].hi == keys[i].hi) ++j;
    fn(std::span<const EdgeHalfedge>(keys.data() + i, j - i));
    i = j;
  }
}

}  // namespace isoquad
