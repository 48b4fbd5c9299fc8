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

// Sorted by (lo, hi, h): halfedges of one edge are adjacent, in triangle order.
inline std::vector<EdgeHalfedge> halfedges_by_edge(std::span<const std::array<uint32_t, 3>> tris) {
  // Sorting one packed 64-bit key (then h) is about twice as fast as comparing three fields.
  std::vector<std::pair<uint64_t, uint32_t>> packed(3 * tris.size());
  for (uint32_t h = 0; h < packed.size(); ++h) {
    const uint32_t a = tris[h / 3][h % 3], b = tris[h / 3][(h % 3 + 1) % 3];
    packed[h] = {(uint64_t(std::min(a, b)) << 32) | std::max(a, b), h};
  }
  std::sort(packed.begin(), packed.end());
  std::vector<EdgeHalfedge> keys(packed.size());
  for (std::size_t i = 0; i < packed.size(); ++i)
    keys[i] = {uint32_t(packed[i].first >> 32), uint32_t(packed[i].first), packed[i].second};
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
