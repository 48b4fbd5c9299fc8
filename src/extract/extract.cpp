#include "extract/extract.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <tuple>

#include "isoquad/error.hpp"
#include "metrics/aabb_tree.hpp"

namespace isoquad {

namespace {

// Faces of one patch bucketed by the unit lattice cells their uv bounding boxes touch.
class ChartIndex {
 public:
  ChartIndex() = default;
  ChartIndex(const std::vector<uint32_t>& faces, const ParamMap& map) : map_(&map) {
    if (faces.empty()) return;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (const uint32_t f : faces)
      for (const UV& p : map.uv[f])
        for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
    x0_ = int64_t(std::floor(lo[0])) - 1;
    y0_ = int64_t(std::floor(lo[1])) - 1;
    nx_ = int64_t(std::floor(hi[0])) - x0_ + 2;
    ny_ = int64_t(std::floor(hi[1])) - y0_ + 2;
    std::vector<uint32_t> count(std::size_t(nx_ * ny_) + 1, 0);
    auto cells = [&](uint32_t f, auto&& fn) {
      double a[2] = {INFINITY, INFINITY}, b[2] = {-INFINITY, -INFINITY};
      for (const UV& p : map.uv[f])
        for (int k = 0; k < 2; ++k) a[k] = std::min(a[k], p[k]), b[k] = std::max(b[k], p[k]);
      for (int64_t y = int64_t(std::floor(a[1])); y <= int64_t(std::floor(b[1])); ++y)
        for (int64_t x = int64_t(std::floor(a[0])); x <= int64_t(std::floor(b[0])); ++x)
          fn(std::size_t((y - y0_) * nx_ + (x - x0_)));
    };
    for (const uint32_t f : faces) cells(f, [&](std::size_t c) { ++count[c + 1]; });
    for (std::size_t c = 1; c < count.size(); ++c) count[c] += count[c - 1];
    start_ = count;
    items_.resize(count.back());
    for (const uint32_t f : faces) cells(f, [&](std::size_t c) { items_[count[c]++] = f; });
  }

  // How many faces contain q under the half-open (top-left) rule: a point on an edge or a
  // vertex shared by several faces is counted once, so a bijective map covers every point it
  // reaches exactly once (QEx-style verification, DESIGN.md §8.4).
  uint32_t count(const UV& q) const {
    if (!map_ || items_.empty()) return 0;
    const int64_t x = int64_t(std::floor(q[0])) - x0_, y = int64_t(std::floor(q[1])) - y0_;
    if (x < 0 || y < 0 || x >= nx_ || y >= ny_) return 0;
    const std::size_t c = std::size_t(y * nx_ + x);
    uint32_t n = 0;
    for (uint32_t i = start_[c]; i < start_[c + 1]; ++i) {
      const auto& t = map_->uv[items_[i]];
      bool in = true;
      for (int k = 0; k < 3 && in; ++k) {
        const UV& a = t[k];
        const UV& b = t[(k + 1) % 3];
        const double o = orient2d(a, b, q);
        // On the edge: only a left edge (going down) or a top edge (going left) keeps it.
        in = o > 0 || (o == 0 && (b[1] < a[1] || (b[1] == a[1] && b[0] < a[0])));
      }
      n += in;
    }
    return n;
  }

  // A face whose uv triangle contains q (closed), with q's barycentric coordinates in it.
  template <class Accept>
  std::optional<std::pair<uint32_t, std::array<double, 3>>> locate(const UV& q,
                                                                   Accept&& accept) const {
    if (!map_ || items_.empty()) return std::nullopt;
    // Faces are bucketed by floor() of their closed bounding boxes, and floor is monotone, so
    // every face whose box contains q is in q's own cell.
    const int64_t x = int64_t(std::floor(q[0])) - x0_, y = int64_t(std::floor(q[1])) - y0_;
    if (x < 0 || y < 0 || x >= nx_ || y >= ny_) return std::nullopt;
    const std::size_t c = std::size_t(y * nx_ + x);
    for (uint32_t i = start_[c]; i < start_[c + 1]; ++i) {
      const uint32_t f = items_[i];
      const auto& t = map_->uv[f];
      const double o0 = orient2d(t[1], t[2], q), o1 = orient2d(t[2], t[0], q),
                   o2 = orient2d(t[0], t[1], q);
      if (o0 < 0 || o1 < 0 || o2 < 0 || !accept(f)) continue;
      const double sum = o0 + o1 + o2;
      if (!(sum > 0)) continue;
      return std::pair{f, std::array<double, 3>{o0 / sum, o1 / sum, o2 / sum}};
    }
    return std::nullopt;
  }

 private:
  const ParamMap* map_ = nullptr;
  int64_t x0_ = 0, y0_ = 0, nx_ = 0, ny_ = 0;
  std::vector<uint32_t> start_, items_;
};

UV apply(const Transition& t, const UV& p) {
  UV r = p;
  for (int k = 0; k < t.k; ++k) r = {-r[1], r[0]};
  return {r[0] + double(t.t[0]), r[1] + double(t.t[1])};
}

// The quads a refined quad is cut into, CCW, in thirds of it: local corner 0 at (0, 0), 1 at
// (3, 0), 2 at (3, 3), 3 at (0, 3). A side with both corners marked gets points at its thirds,
// a side with one marked corner a point a third from that corner, so the quads across a side
// agree on its points (Schneiders' 3-refinement, by marked corners).
using RefineTemplate = std::vector<std::array<std::array<int, 2>, 4>>;
// Corner 0 marked: a small quad at it and two around.
const RefineTemplate kRefineCorner{{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}},
                                   {{{1, 0}, {3, 0}, {3, 3}, {1, 1}}},
                                   {{{1, 1}, {3, 3}, {0, 3}, {0, 1}}}};
// Corners 0 and 1 marked: three small quads along their side, then three narrowing to the far
// side.
const RefineTemplate kRefineSide{
    {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}}, {{{1, 0}, {2, 0}, {2, 1}, {1, 1}}},
    {{{2, 0}, {3, 0}, {3, 1}, {2, 1}}}, {{{0, 1}, {1, 1}, {1, 2}, {0, 3}}},
    {{{1, 1}, {2, 1}, {2, 2}, {1, 2}}}, {{{2, 1}, {3, 1}, {3, 3}, {2, 2}}},
    {{{1, 2}, {2, 2}, {3, 3}, {0, 3}}}};
// All four marked: three by three.
const RefineTemplate kRefineAll = [] {
  RefineTemplate t;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) t.push_back({{{x, y}, {x + 1, y}, {x + 1, y + 1}, {x, y + 1}}});
  return t;
}();

}  // namespace

double distance_to_quad(const std::array<Vec3, 4>& p, const Vec3& x) {
  const Vec3 c = 0.25 * (p[0] + p[1] + p[2] + p[3]);
  double best = INFINITY;
  for (int k = 0; k < 4; ++k)
    best = std::min(best, norm(closest_point_on_triangle(x, p[k], p[(k + 1) % 4], c) - x));
  return best;
}

double distance_to_quad(const std::vector<Vec3>& positions, const std::array<uint32_t, 4>& q,
                        const Vec3& x) {
  return distance_to_quad({positions[q[0]], positions[q[1]], positions[q[2]], positions[q[3]]}, x);
}

std::vector<std::array<Vec3, 3>> fan_triangles(const QuadMesh& qm) {
  std::vector<std::array<Vec3, 3>> t;
  t.reserve(2 * qm.quads.size());
  for (const auto& q : qm.quads) {
    t.push_back({qm.positions[q[0]], qm.positions[q[1]], qm.positions[q[2]]});
    t.push_back({qm.positions[q[0]], qm.positions[q[2]], qm.positions[q[3]]});
  }
  return t;
}

std::vector<std::array<Vec3, 3>> face_triangles(const TriMesh& surface) {
  std::vector<std::array<Vec3, 3>> t;
  t.reserve(surface.num_faces());
  for (const Tri& f : surface.faces())
    t.push_back({surface.position(f[0]), surface.position(f[1]), surface.position(f[2])});
  return t;
}

LatticeQuads lattice_quads(const MetaMesh& meta, const Layout& layout) {
  const uint32_t np = uint32_t(layout.charts.size());
  constexpr int64_t S = LatticeQuads::kScale;
  LatticeQuads out;
  out.meta_vertices = uint32_t(meta.vertices.size());
  // Lattice ids: meta-vertices, then the inner points of every meta-edge, then patch interiors.
  std::vector<uint32_t> edge_first(meta.edges.size());
  uint32_t next = uint32_t(meta.vertices.size());
  for (uint32_t e = 0; e < meta.edges.size(); ++e) {
    edge_first[e] = next;
    next += uint32_t(layout.length[e] - 1);
  }
  // Representative (patch, lattice point) of every id: the first patch that owns it, the left
  // patch for meta-edge points; meta-vertices are placed exactly.
  auto& points = out.points;
  points.resize(next);
  auto use = [&](uint32_t id, uint32_t p) {
    auto& u = points[id].patches;
    if (u[0] == kInvalid)
      u = {p, p};
    else
      u[1] = p;
  };
  out.side_edge.resize(np);
  for (uint32_t p = 0; p < np; ++p) {
    const Chart& ch = layout.charts[p];
    const int64_t W = ch.width, H = ch.height;
    std::vector<uint32_t> g(std::size_t((W + 1) * (H + 1)), kInvalid);
    auto at = [&](Lattice q) -> uint32_t& { return g[std::size_t(q[1] * (W + 1) + q[0])]; };
    auto& side = out.side_edge[p];
    side.assign(std::size_t(2 * (W + H)), kInvalid);
    const MetaFace& face = meta.faces[p];
    for (uint32_t i = 0; i < face.cycle.size(); ++i) {
      const BoundaryItem& item = face.cycle[i];
      const int64_t x = layout.length[item.edge];
      const Lattice a = ch.item_position[i];
      const Lattice b = ch.item_position[(i + 1) % face.cycle.size()];
      const Lattice d{(b[0] - a[0]) / x, (b[1] - a[1]) / x};
      at(a) = face.start_vertex(i, meta.edges);
      for (int64_t s = 0; s < x; ++s) {
        const Lattice q{a[0] + s * d[0], a[1] + s * d[1]};
        const std::size_t k = LatticeQuads::side_segment(W, H, q, {q[0] + d[0], q[1] + d[1]});
        if (k < side.size()) side[k] = item.edge;
        if (s == 0) continue;
        const uint32_t id = edge_first[item.edge] + uint32_t((item.forward ? s : x - s) - 1);
        at(q) = id;
        use(id, p);
        if (points[id].patch == kInvalid || item.forward)
          points[id].patch = p, points[id].at = {S * q[0], S * q[1]}, points[id].edge = item.edge;
      }
    }
    for (int64_t j = 1; j < H; ++j)
      for (int64_t i = 1; i < W; ++i) {
        at({i, j}) = next;
        LatticeQuads::Point pt;
        pt.patch = p;
        pt.at = {S * i, S * j};
        pt.patches = {p, p};
        points.push_back(pt);
        ++next;
      }
    for (const uint32_t id : g)
      if (id == kInvalid)
        throw Error(ErrorKind::internal, "E601", "a lattice point of a patch has no id");
    for (int64_t j = 0; j < H; ++j)
      for (int64_t i = 0; i < W; ++i) {
        out.quads.push_back({at({i, j}), at({i + 1, j}), at({i + 1, j + 1}), at({i, j + 1})});
        out.corner_at.push_back({{{S * i, S * j},
                                  {S * (i + 1), S * j},
                                  {S * (i + 1), S * (j + 1)},
                                  {S * i, S * (j + 1)}}});
        out.quad_patch.push_back(p);
        out.level.push_back(0);
      }
  }
  return out;
}

std::size_t LatticeQuads::side_segment(int64_t W, int64_t H, Lattice u, Lattice v) {
  const int64_t x = std::min(u[0], v[0]), y = std::min(u[1], v[1]);
  if (u[1] == v[1] && u[1] == 0) return std::size_t(x);
  if (u[0] == v[0] && u[0] == W) return std::size_t(W + y);
  if (u[1] == v[1] && u[1] == H) return std::size_t(W + H + x);
  if (u[0] == v[0] && u[0] == 0) return std::size_t(2 * W + H + y);
  return SIZE_MAX;
}

uint32_t refine_lattice_quads(LatticeQuads& lq, const Layout& layout, std::vector<char> mark) {
  constexpr int64_t S = LatticeQuads::kScale;
  mark.resize(lq.points.size(), 0);
  // Closed: no quad keeps three marked corners or two opposite ones.
  for (bool changed = true; changed;) {
    changed = false;
    for (const auto& c : lq.quads) {
      const int n = mark[c[0]] + mark[c[1]] + mark[c[2]] + mark[c[3]];
      if (n == 3 || (n == 2 && mark[c[0]] == mark[c[2]]))
        for (const uint32_t id : c) changed |= !mark[id], mark[id] = 1;
    }
  }
  // Points keep their ids (new ones follow) and the borders stay: taken over, not copied.
  LatticeQuads out;
  out.meta_vertices = lq.meta_vertices;
  out.points = std::move(lq.points);
  out.side_edge = std::move(lq.side_edge);
  // Side points are shared with the quad across the side: keyed by the side's end ids and the
  // point's third from the smaller one.
  std::map<std::tuple<uint32_t, uint32_t, int>, uint32_t> side_points;
  uint32_t refined = 0;
  for (std::size_t f = 0; f < lq.quads.size(); ++f) {
    const auto& c = lq.quads[f];
    const auto& ca = lq.corner_at[f];
    const uint32_t p = lq.quad_patch[f];
    const int pattern = mark[c[0]] | mark[c[1]] << 1 | mark[c[2]] << 2 | mark[c[3]] << 3;
    if (pattern == 0) {
      out.quads.push_back(c);
      out.corner_at.push_back(ca);
      out.quad_patch.push_back(p);
      out.level.push_back(lq.level[f]);
      continue;
    }
    if (lq.level[f] >= LatticeQuads::kMaxLevel)
      throw Error(ErrorKind::internal, "E602",
                  "a quad is refined more often than its chart allows");
    ++refined;
    // The template turned so that its marked corners are local corner 0 (and 1), or all four.
    int r = 0;
    const RefineTemplate* t = &kRefineAll;
    if (pattern != 15) {
      const bool one = pattern == 1 || pattern == 2 || pattern == 4 || pattern == 8;
      t = one ? &kRefineCorner : &kRefineSide;
      while (((pattern >> r) & 1) == 0 || (!one && ((pattern >> ((r + 1) % 4)) & 1) == 0)) ++r;
    }
    const int64_t W = layout.charts[p].width, H = layout.charts[p].height;
    // Local (s, u) in thirds -> chart coordinates, bilinear in the quad's corners (exact: they
    // are multiples of 9^(kMaxLevel - level)).
    auto chart_at = [&](int s, int u) {
      const int64_t w[4] = {(3 - s) * (3 - u), s * (3 - u), s * u, (3 - s) * u};
      std::array<int64_t, 2> x{0, 0};
      for (int k = 0; k < 4; ++k)
        for (int d = 0; d < 2; ++d) x[d] += w[k] * ca[(r + k) % 4][d];
      return std::array<int64_t, 2>{x[0] / 9, x[1] / 9};
    };
    std::array<uint32_t, 16> inner;  // ids of the points inside, by (s, u) in thirds
    inner.fill(kInvalid);
    auto point = [&](std::array<int, 2> l) -> uint32_t {
      const int s = l[0], u = l[1];
      const bool s_end = s == 0 || s == 3, u_end = u == 0 || u == 3;
      if (s_end && u_end) return c[(r + (s == 3 ? (u == 3 ? 2 : 1) : (u == 3 ? 3 : 0))) % 4];
      const std::array<int64_t, 2> at = chart_at(s, u);
      LatticeQuads::Point pt;
      pt.patch = p;
      pt.at = at;
      pt.patches = {p, p};
      if (!s_end && !u_end) {
        uint32_t& id = inner[std::size_t(4 * u + s)];
        if (id == kInvalid) id = uint32_t(out.points.size()), out.points.push_back(pt);
        return id;
      }
      // On a side, from local corner a towards local corner b, k thirds along.
      int a, b, k;
      if (u == 0)
        a = 0, b = 1, k = s;
      else if (s == 3)
        a = 1, b = 2, k = u;
      else if (u == 3)
        a = 3, b = 2, k = s;
      else
        a = 0, b = 3, k = u;
      uint32_t ia = c[(r + a) % 4], ib = c[(r + b) % 4];
      if (ia > ib) std::swap(ia, ib), k = 3 - k;
      auto [it, fresh] = side_points.try_emplace({ia, ib, k}, uint32_t(out.points.size()));
      if (fresh) {
        // On the chart's border (a meta-edge), the unit segment it lies in says which.
        const auto &pa = ca[(r + a) % 4], &pb = ca[(r + b) % 4];
        const bool on_border = (pa[1] == pb[1] && (pa[1] == 0 || pa[1] == S * H)) ||
                               (pa[0] == pb[0] && (pa[0] == 0 || pa[0] == S * W));
        if (on_border) {
          const Lattice lo{std::min(pa[0], pb[0]) / S, std::min(pa[1], pb[1]) / S};
          const Lattice hi{pa[0] == pb[0] ? lo[0] : lo[0] + 1, pa[1] == pb[1] ? lo[1] : lo[1] + 1};
          const std::size_t seg = LatticeQuads::side_segment(W, H, lo, hi);
          if (seg < out.side_edge[p].size()) pt.edge = out.side_edge[p][seg];
        }
        out.points.push_back(pt);
      } else {
        out.points[it->second].patches[1] = p;
      }
      return it->second;
    };
    for (const auto& q : *t) {
      out.quads.push_back({point(q[0]), point(q[1]), point(q[2]), point(q[3])});
      out.corner_at.push_back({chart_at(q[0][0], q[0][1]), chart_at(q[1][0], q[1][1]),
                               chart_at(q[2][0], q[2][1]), chart_at(q[3][0], q[3][1])});
      out.quad_patch.push_back(p);
      out.level.push_back(uint8_t(lq.level[f] + 1));
    }
  }
  lq = std::move(out);
  return refined;
}

QuadMesh place_quads(const RefinedMesh& refined, const TriMesh& base,
                     const FaceData<uint32_t>& labels, const MetaMesh& meta, const Layout& layout,
                     const Param& param, const LatticeQuads& lq, ExtractReport& report) {
  const auto t0 = std::chrono::steady_clock::now();
  const TriMesh& mesh = refined.mesh;
  const uint32_t np = uint32_t(layout.charts.size());
  const uint32_t n = uint32_t(lq.points.size());
  QuadMesh out;
  out.quads = lq.quads;
  out.quad_patch = lq.quad_patch;
  report.quads = uint32_t(lq.quads.size());
  std::vector<std::vector<uint32_t>> patch_faces(np);
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) patch_faces[labels[f]].push_back(f);
  std::vector<ChartIndex> relaxed(np), locked(np);
  for (uint32_t p = 0; p < np; ++p) {
    relaxed[p] = ChartIndex(patch_faces[p], param.map);
    locked[p] = ChartIndex(patch_faces[p], param.locked);
  }
  auto surface_point = [&](uint32_t f, const std::array<double, 3>& l) {
    SurfacePoint s{refined.base_face[f], {0, 0, 0}};
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) s.bary[k] += l[c] * refined.corner_bary[f][c][k];
    return s;
  };
  auto uv_of = [](const LatticeQuads::Point& pt) {
    return UV{double(pt.at[0]) / double(LatticeQuads::kScale),
              double(pt.at[1]) / double(LatticeQuads::kScale)};
  };
  const auto any = [](uint32_t) { return true; };
  std::vector<char> suspect(np, 0);
  out.surface.resize(n);
  out.vertex_meta_vertex.assign(n, kInvalid);
  out.placed.assign(n, QuadMesh::Placed::meta);
  out.vertex_meta_edge.assign(n, kInvalid);
  for (uint32_t id = lq.meta_vertices; id < n; ++id) out.vertex_meta_edge[id] = lq.points[id].edge;
  for (uint32_t id = 0; id < n; ++id) {
    if (id < lq.meta_vertices) {
      out.surface[id] = refined.vertex_origin(meta.vertices[id].vertex);
      out.vertex_meta_vertex[id] = id;
      ++report.meta;
      continue;
    }
    const LatticeQuads::Point& r = lq.points[id];
    const UV q = uv_of(r);
    std::optional<std::pair<uint32_t, std::array<double, 3>>> hit = relaxed[r.patch].locate(q, any);
    // Coverage is counted chart by chart: within one chart all faces share their corners' uv
    // bit for bit, so the half-open rule counts every point once; across a seam the two sides
    // agree only to rounding and the rule is not invariant under the quarter turns, so a point
    // on a seam may count once on each side, which is not a fold.
    uint32_t cover = relaxed[r.patch].count(q);
    QuadMesh::Placed how = QuadMesh::Placed::direct;
    // Across the seams of the patch: the point may be covered by a neighbour whose seam
    // bulges into this rectangle. Only faces near that seam are accepted, so that two
    // meta-edges between the same patches (different transitions) cannot be confused.
    const MetaFace& face = meta.faces[r.patch];
    for (uint32_t i = 0; i < face.cycle.size(); ++i) {
      const MetaEdge& me = meta.edges[face.cycle[i].edge];
      if (me.right == kInvalid) continue;
      const bool left = me.left == r.patch;
      const uint32_t other = left ? me.right : me.left;
      const Transition t = left ? layout.transition[face.cycle[i].edge]
                                : layout.transition[face.cycle[i].edge].inverse();
      // Distance from q to the meta-edge's segment in this chart: at most 2 lattice units.
      const Lattice a = layout.charts[r.patch].item_position[i];
      const Lattice b = layout.charts[r.patch].item_position[(i + 1) % face.cycle.size()];
      const double lx = double(b[0] - a[0]), ly = double(b[1] - a[1]);
      const double len2 = lx * lx + ly * ly;
      const double s = std::clamp(((q[0] - a[0]) * lx + (q[1] - a[1]) * ly) / len2, 0.0, 1.0);
      if (std::hypot(q[0] - (a[0] + s * lx), q[1] - (a[1] + s * ly)) > 2.0) continue;
      const UV qo = apply(t, q);
      cover = std::max(cover, relaxed[other].count(qo));
      if (!hit) {
        hit = relaxed[other].locate(qo, any);
        if (hit) how = QuadMesh::Placed::across;
      }
    }
    if (cover > 1) {
      ++report.multiply_covered;
      suspect[r.patch] = 1;
    }
    if (!hit) {
      hit = locked[r.patch].locate(q, any);
      how = QuadMesh::Placed::locked;
    }
    if (!hit)
      throw Error(ErrorKind::internal, "E601",
                  fmt::format("lattice point ({:g}, {:g}) of patch {} is not covered by the map",
                              q[0], q[1], r.patch));
    out.surface[id] = surface_point(hit->first, hit->second);
    out.placed[id] = how;
  }
  // The verifier's verdict: a patch with a lattice point covered twice is not bijective there
  // (which the certificate rules out); its lattice points, seams included, take the locked
  // map's geometry, which tiles every rectangle exactly.
  const uint32_t locked_patches = uint32_t(std::count(suspect.begin(), suspect.end(), 1));
  report.patches_locked += locked_patches;
  for (uint32_t id = lq.meta_vertices; id < n && locked_patches > 0; ++id) {
    const LatticeQuads::Point& r = lq.points[id];
    if ((!suspect[r.patches[0]] && !suspect[r.patches[1]]) ||
        out.placed[id] == QuadMesh::Placed::locked)
      continue;
    // The id's own representative point, in its own patch's chart.
    auto hit = locked[r.patch].locate(uv_of(r), any);
    if (!hit) continue;  // stays where the relaxed map put it
    out.surface[id] = surface_point(hit->first, hit->second);
    out.placed[id] = QuadMesh::Placed::locked;
  }
  for (uint32_t id = lq.meta_vertices; id < n; ++id) {
    if (out.placed[id] == QuadMesh::Placed::direct) ++report.direct;
    if (out.placed[id] == QuadMesh::Placed::across) ++report.across;
    if (out.placed[id] == QuadMesh::Placed::locked) ++report.locked;
  }
  out.positions.resize(n);
  for (uint32_t id = 0; id < n; ++id) {
    const SurfacePoint& s = out.surface[id];
    const Tri& t = base.face(s.face);
    out.positions[id] = s.bary[0] * base.position(t[0]) + s.bary[1] * base.position(t[1]) +
                        s.bary[2] * base.position(t[2]);
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

QuadMesh extract_quads(const RefinedMesh& refined, const TriMesh& base,
                       const FaceData<uint32_t>& labels, const MetaMesh& meta, const Layout& layout,
                       const Param& param, ExtractReport& report) {
  return place_quads(refined, base, labels, meta, layout, param, lattice_quads(meta, layout),
                     report);
}

PolyMesh as_poly(const QuadMesh& qm) {
  PolyMesh p;
  p.positions = qm.positions;
  for (const auto& q : qm.quads) p.add_face({q[0], q[1], q[2], q[3]});
  return p;
}

}  // namespace isoquad
