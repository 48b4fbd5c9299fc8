#include <algorithm>
#include <cmath>

#include "prep/steps.hpp"

namespace isoquad::prep {

namespace {

// Ear clipping in the plane of the polygon's Newell normal, always clipping the first ear in
// the polygon's order; a fan for what is left if the polygon is not simple (no ear can be
// found). Each corner's ear test is kept, with the corner found inside its triangle, and redone
// only when a neighbour or that corner is clipped: the same ears as testing every corner again
// after each clip, in O(n^2) rather than O(n^3) (a 400-gon took 6 s under the sanitizers, a
// 30,000-gon would take hours).
void ear_clip(const std::vector<Vec3>& P, const std::vector<uint32_t>& poly,
              std::vector<Tri>& out) {
  const uint32_t m = uint32_t(poly.size());
  Vec3 n;
  for (uint32_t i = 0; i < m; ++i) n += cross(P[poly[i]], P[poly[(i + 1) % m]]);
  const Vec3 axis = normalized(n);
  const Vec3 helper = std::fabs(axis.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 ex = normalized(cross(helper, axis)), ey = cross(axis, ex);
  std::vector<std::pair<double, double>> uv(m);  // by position in `poly`, as all below
  for (uint32_t i = 0; i < m; ++i) uv[i] = {dot(P[poly[i]], ex), dot(P[poly[i]], ey)};
  auto orient = [&](uint32_t a, uint32_t b, uint32_t c) {
    const auto [ax, ay] = uv[a];
    const auto [bx, by] = uv[b];
    const auto [cx, cy] = uv[c];
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
  };
  std::vector<uint32_t> prev(m), next(m);
  for (uint32_t i = 0; i < m; ++i) prev[i] = (i + m - 1) % m, next[i] = (i + 1) % m;
  std::vector<char> ear(m, 0);
  std::vector<uint32_t> inside(m, kInvalid);     // a corner inside corner i's triangle
  std::vector<std::vector<uint32_t>> blocks(m);  // corners that corner i was found inside
  auto test = [&](uint32_t b) {
    const uint32_t a = prev[b], c = next[b];
    ear[b] = 0;
    inside[b] = kInvalid;
    if (orient(a, b, c) <= 0) return;  // reflex or flat corner
    for (uint32_t p = next[c]; p != a; p = next[p])
      if (orient(a, b, p) >= 0 && orient(b, c, p) >= 0 && orient(c, a, p) >= 0) {
        inside[b] = p;
        blocks[p].push_back(b);
        return;
      }
    ear[b] = 1;
  };
  for (uint32_t i = 0; i < m; ++i) test(i);
  uint32_t first = 0, left = m;
  while (left > 3) {
    uint32_t b = first;
    while (!ear[b] && next[b] != first) b = next[b];
    if (!ear[b]) break;
    const uint32_t a = prev[b], c = next[b];
    out.push_back({poly[a], poly[b], poly[c]});
    next[a] = c, prev[c] = a;
    if (first == b) first = c;
    --left;
    ear[b] = 0;
    for (const uint32_t q : blocks[b])
      if (inside[q] == b && q != a && q != c) test(q);
    test(a);
    test(c);
  }
  for (uint32_t b = next[first]; next[b] != first; b = next[b])
    out.push_back({poly[first], poly[b], poly[next[b]]});
}

}  // namespace

Soup triangulate(const PolyMesh& soup, const std::vector<uint32_t>& weld, InputReport& report) {
  Soup s;
  const auto& P = soup.positions;
  std::vector<uint32_t> poly;
  std::vector<Tri> tris;
  for (std::size_t f = 0; f < soup.num_faces(); ++f) {
    poly.clear();
    for (uint32_t v : soup.face(f)) {
      const uint32_t w = weld[v];
      if (poly.empty() || poly.back() != w) poly.push_back(w);
    }
    while (poly.size() > 1 && poly.back() == poly.front()) poly.pop_back();
    std::vector<uint32_t> sorted = poly;
    std::sort(sorted.begin(), sorted.end());
    if (poly.size() < 3 || std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
      ++report.degenerate_faces;  // collapsed by welding (or a repeated vertex)
      continue;
    }
    tris.clear();
    if (poly.size() == 3) {
      tris.push_back({poly[0], poly[1], poly[2]});
    } else if (poly.size() == 4) {
      // Split along the shorter diagonal.
      if (norm(P[poly[0]] - P[poly[2]]) <= norm(P[poly[1]] - P[poly[3]])) {
        tris.push_back({poly[0], poly[1], poly[2]});
        tris.push_back({poly[0], poly[2], poly[3]});
      } else {
        tris.push_back({poly[1], poly[2], poly[3]});
        tris.push_back({poly[1], poly[3], poly[0]});
      }
    } else {
      ear_clip(P, poly, tris);
    }
    for (const Tri& t : tris) {
      s.tris.push_back(t);
      s.tri_input.push_back(uint32_t(f));
    }
  }
  // Compact to the vertices that are used, keeping input order.
  std::vector<uint32_t> remap(soup.num_vertices(), kInvalid);
  for (const Tri& t : s.tris)
    for (uint32_t v : t) remap[v] = 0;
  for (uint32_t v = 0; v < remap.size(); ++v) {
    if (remap[v] == kInvalid) {
      if (weld[v] == v) ++report.unused_vertices;
      continue;
    }
    remap[v] = uint32_t(s.positions.size());
    s.positions.push_back(P[v]);
    s.vertex_input.push_back(v);
  }
  for (Tri& t : s.tris)
    for (uint32_t& v : t) v = remap[v];
  return s;
}

void drop_duplicate_faces(Soup& soup, InputReport& report) {
  std::vector<std::pair<Tri, uint32_t>> keys(soup.tris.size());
  for (uint32_t t = 0; t < soup.tris.size(); ++t) {
    Tri k = soup.tris[t];
    std::sort(k.begin(), k.end());
    keys[t] = {k, t};
  }
  std::sort(keys.begin(), keys.end());
  std::vector<char> drop(soup.tris.size(), 0);
  for (std::size_t i = 1; i < keys.size(); ++i)
    if (keys[i].first == keys[i - 1].first) drop[keys[i].second] = 1;  // keep the earliest
  std::size_t out = 0;
  for (std::size_t t = 0; t < soup.tris.size(); ++t) {
    if (drop[t]) {
      ++report.duplicate_faces;
      continue;
    }
    soup.tris[out] = soup.tris[t];
    soup.tri_input[out] = soup.tri_input[t];
    ++out;
  }
  soup.tris.resize(out);
  soup.tri_input.resize(out);
}

}  // namespace isoquad::prep
