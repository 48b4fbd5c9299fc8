#include <algorithm>
#include <array>
#include <iterator>
#include <unordered_map>

#include "prep/steps.hpp"

namespace isoquad::prep {

namespace {

double area_of(const std::vector<Vec3>& x, const Tri& t) {
  return 0.5 * norm(cross(x[t[1]] - x[t[0]], x[t[2]] - x[t[0]]));
}

// A triangle whose shortest edge is below this share of its longest is a needle (its edge is
// collapsed); otherwise a zero-area triangle is a cap, a vertex on its longest edge (flipped).
constexpr double kNeedleShare = 1e-3;
constexpr uint32_t kMaxPasses = 64;

// One pass's view of the triangles: halfedges (3t + i runs from corner i to corner i + 1),
// each vertex's triangles and neighbours, and the vertices a change of this pass touched.
struct Pass {
  const std::vector<Tri>& tris;
  const std::vector<char>& alive;
  std::unordered_map<uint64_t, uint32_t> at;
  std::vector<std::vector<uint32_t>> faces, nbr;
  std::vector<char> boundary, touched;

  Pass(const std::vector<Tri>& t, const std::vector<char>& a, std::size_t n)
      : tris(t), alive(a), faces(n), nbr(n), boundary(n, 0), touched(n, 0) {
    at.reserve(3 * tris.size());
    for (uint32_t f = 0; f < tris.size(); ++f) {
      if (!alive[f]) continue;
      for (uint32_t i = 0; i < 3; ++i) {
        const uint32_t v = tris[f][i], w = tris[f][(i + 1) % 3];
        at[edge_key(v, w)] = 3 * f + i;
        faces[v].push_back(f);
        nbr[v].push_back(w);
        nbr[w].push_back(v);
      }
    }
    for (auto& list : nbr) {
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
    }
    for (const auto& [key, h] : at) {
      const uint32_t v = uint32_t(key >> 32), w = uint32_t(key);
      if (!at.count(edge_key(w, v))) boundary[v] = boundary[w] = 1;
    }
  }
  // The triangle across the edge v -> w (on w -> v), or kInvalid on the boundary.
  uint32_t across(uint32_t v, uint32_t w) const {
    const auto it = at.find(edge_key(w, v));
    return it == at.end() ? kInvalid : it->second / 3;
  }
  uint32_t opposite(uint32_t f, uint32_t v, uint32_t w) const {
    for (const uint32_t u : tris[f])
      if (u != v && u != w) return u;
    return kInvalid;
  }
  bool untouched_around(uint32_t v) const {
    return !touched[v] &&
           std::none_of(nbr[v].begin(), nbr[v].end(), [&](uint32_t w) { return touched[w]; });
  }
  void touch_around(uint32_t v) {
    touched[v] = 1;
    for (const uint32_t w : nbr[v]) touched[w] = 1;
  }
};

}  // namespace

// Zero-area triangles (area below kZeroArea) leave the map's linear system singular and no
// quad can be valid on them. Each pass visits the triangles in order and repairs those whose
// neighbourhood no earlier repair of the pass touched:
//  - a needle (one edge below kNeedleShare of the longest) loses that edge: its end off the
//    boundary (or the higher id) merges into the other, if the link condition holds (the two
//    ends share exactly the neighbours opposite the edge) and the edge does not join two
//    boundary vertices across the interior, so the topology and manifoldness stay;
//  - a cap (a vertex on its longest edge) has that edge flipped, if the edge is interior, the
//    new edge does not exist yet and both new triangles have area and face as the neighbour
//    did: the two new triangles cover the neighbour exactly. A cap on the boundary goes, its
//    vertex joining the boundary, unless that vertex is on the boundary already.
// Deterministic (triangles and passes in order).
ZeroAreaRepair repair_zero_area(std::vector<Vec3>& positions, std::vector<Tri>& tris,
                                std::vector<uint32_t>& vertex_input,
                                std::vector<uint32_t>& tri_input) {
  ZeroAreaRepair r;
  std::vector<char> alive(tris.size(), 1);
  auto zero = [&](uint32_t f) { return alive[f] && area_of(positions, tris[f]) < kZeroArea; };
  bool any = false;
  for (uint32_t f = 0; f < tris.size() && !any; ++f) any = zero(f);
  if (!any) return r;
  uint32_t living = uint32_t(tris.size());
  for (uint32_t round = 0; round < kMaxPasses; ++round) {
    Pass p(tris, alive, positions.size());
    uint32_t changed = 0;
    for (uint32_t f = 0; f < tris.size(); ++f) {
      if (!zero(f)) continue;
      const Tri t = tris[f];
      if (std::any_of(t.begin(), t.end(), [&](uint32_t v) { return p.touched[v]; })) continue;
      std::array<double, 3> len;  // edge i: corner i -> i + 1
      for (int i = 0; i < 3; ++i) len[i] = norm(positions[t[(i + 1) % 3]] - positions[t[i]]);
      const int shortest = int(std::min_element(len.begin(), len.end()) - len.begin());
      const int longest = int(std::max_element(len.begin(), len.end()) - len.begin());
      if (len[shortest] <= kNeedleShare * len[longest]) {
        uint32_t keep = t[shortest], gone = t[(shortest + 1) % 3];
        if ((p.boundary[gone] && !p.boundary[keep]) ||
            (p.boundary[gone] == p.boundary[keep] && gone < keep))
          std::swap(keep, gone);
        const uint32_t g = p.across(t[shortest], t[(shortest + 1) % 3]);
        if (p.boundary[keep] && p.boundary[gone] && g != kInvalid) continue;
        if (living < 6 || !p.untouched_around(keep) || !p.untouched_around(gone)) continue;
        std::vector<uint32_t> opposite{p.opposite(f, keep, gone)};
        if (g != kInvalid) opposite.push_back(p.opposite(g, keep, gone));
        std::sort(opposite.begin(), opposite.end());
        std::vector<uint32_t> common;
        std::set_intersection(p.nbr[keep].begin(), p.nbr[keep].end(), p.nbr[gone].begin(),
                              p.nbr[gone].end(), std::back_inserter(common));
        if (common != opposite) continue;
        r.moved = std::max(r.moved, norm(positions[keep] - positions[gone]));
        p.touch_around(keep);
        p.touch_around(gone);
        for (const uint32_t h : p.faces[gone]) {
          if (h == f || h == g) continue;
          for (uint32_t& v : tris[h])
            if (v == gone) v = keep;
        }
        alive[f] = 0;
        if (g != kInvalid) alive[g] = 0;
        living -= g != kInvalid ? 2 : 1;
        ++r.collapsed;
        ++changed;
      } else {
        const uint32_t a = t[longest], b = t[(longest + 1) % 3], c = t[(longest + 2) % 3];
        const uint32_t g = p.across(a, b);
        if (g == kInvalid) {
          // On the boundary: the cap goes and c joins the boundary between a and b (the
          // boundary runs a, c, b: the same curve). Not where c is on the boundary already: it
          // would then have two fans.
          if (p.boundary[c] || living < 6 || !p.untouched_around(c)) continue;
          p.touch_around(c);
          alive[f] = 0;
          --living;
          ++r.dropped;
          ++changed;
          continue;
        }
        const uint32_t d = p.opposite(g, a, b);
        if (d == kInvalid || d == c || p.touched[d] || p.at.count(edge_key(c, d)) ||
            p.at.count(edge_key(d, c)))
          continue;
        const Tri one{c, a, d}, two{d, b, c};
        const Vec3 n = cross(positions[tris[g][1]] - positions[tris[g][0]],
                             positions[tris[g][2]] - positions[tris[g][0]]);
        auto fits = [&](const Tri& s) {
          const Vec3 m =
              cross(positions[s[1]] - positions[s[0]], positions[s[2]] - positions[s[0]]);
          return area_of(positions, s) >= kZeroArea && dot(m, n) > 0;
        };
        if (!fits(one) || !fits(two)) continue;
        for (const uint32_t v : {a, b, c, d}) p.touched[v] = 1;
        tris[f] = one;
        tris[g] = two;
        ++r.flipped;
        ++changed;
      }
    }
    if (changed == 0) break;
  }
  // Compact: the living triangles and the vertices they use, each in their order.
  std::vector<uint32_t> index(positions.size(), kInvalid);
  for (uint32_t f = 0; f < tris.size(); ++f)
    if (alive[f])
      for (const uint32_t v : tris[f]) index[v] = 0;
  std::vector<Vec3> x;
  std::vector<uint32_t> vin, fin;
  for (uint32_t v = 0; v < positions.size(); ++v) {
    if (index[v] == kInvalid) continue;
    index[v] = uint32_t(x.size());
    x.push_back(positions[v]);
    vin.push_back(vertex_input[v]);
  }
  std::vector<Tri> kept;
  for (uint32_t f = 0; f < tris.size(); ++f) {
    if (!alive[f]) continue;
    Tri t = tris[f];
    for (uint32_t& v : t) v = index[v];
    kept.push_back(t);
    fin.push_back(tri_input[f]);
  }
  positions = std::move(x);
  vertex_input = std::move(vin);
  tris = std::move(kept);
  tri_input = std::move(fin);
  for (uint32_t f = 0; f < tris.size(); ++f) r.left += area_of(positions, tris[f]) < kZeroArea;
  return r;
}

}  // namespace isoquad::prep
