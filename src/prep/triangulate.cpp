#include <algorithm>
#include <cmath>

#include "prep/steps.hpp"

namespace isoquad::prep {

namespace {

// Ear clipping in the plane of the polygon's Newell normal; a fan for what is left if the
// polygon is not simple (no ear can be found).
void ear_clip(const std::vector<Vec3>& P, std::vector<uint32_t> poly, std::vector<Tri>& out) {
  Vec3 n;
  for (std::size_t i = 0; i < poly.size(); ++i)
    n += cross(P[poly[i]], P[poly[(i + 1) % poly.size()]]);
  const Vec3 axis = normalized(n);
  const Vec3 helper = std::fabs(axis.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 ex = normalized(cross(helper, axis)), ey = cross(axis, ex);
  auto uv = [&](uint32_t v) { return std::pair<double, double>{dot(P[v], ex), dot(P[v], ey)}; };
  auto orient = [&](uint32_t a, uint32_t b, uint32_t c) {
    const auto [ax, ay] = uv(a);
    const auto [bx, by] = uv(b);
    const auto [cx, cy] = uv(c);
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
  };
  while (poly.size() > 3) {
    bool clipped = false;
    const std::size_t m = poly.size();
    for (std::size_t i = 0; i < m && !clipped; ++i) {
      const uint32_t a = poly[(i + m - 1) % m], b = poly[i], c = poly[(i + 1) % m];
      if (orient(a, b, c) <= 0) continue;  // reflex or flat corner
      bool empty = true;
      for (std::size_t j = 0; j < m && empty; ++j) {
        const uint32_t p = poly[j];
        if (p == a || p == b || p == c) continue;
        empty = !(orient(a, b, p) >= 0 && orient(b, c, p) >= 0 && orient(c, a, p) >= 0);
      }
      if (!empty) continue;
      out.push_back({a, b, c});
      poly.erase(poly.begin() + std::ptrdiff_t(i));
      clipped = true;
    }
    if (!clipped) break;
  }
  for (std::size_t i = 1; i + 1 < poly.size(); ++i) out.push_back({poly[0], poly[i], poly[i + 1]});
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
