#include "marching_tets.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <unordered_map>
#include <vector>

namespace isoquad::test {

namespace {

// A cut is kept this far (of the grid edge) from the grid vertices: the slivers it would make
// nearer are relaxed afterwards, but a triangle of zero area could not be.
constexpr double kCutClamp = 0.05;

struct Grid {
  Vec3 lo;
  double h;
  int nx, ny, nz;
  uint64_t id(int i, int j, int k) const {
    return uint64_t(i) + uint64_t(nx) * (j + uint64_t(ny) * k);
  }
  Vec3 point(uint64_t v) const {
    const uint64_t i = v % nx, j = (v / nx) % ny, k = v / (uint64_t(nx) * ny);
    return lo + h * Vec3{double(i), double(j), double(k)};
  }
};

// Builds the triangles of one tetrahedron's zero set into `out`, oriented towards f > 0.
class TetCutter {
 public:
  TetCutter(const Grid& g, const std::vector<double>& values, PolyMesh& out)
      : g_(g), values_(values), out_(out) {}

  void tet(const std::array<uint64_t, 4>& v) {
    std::array<uint64_t, 4> in{}, outside{};
    int n_in = 0, n_out = 0;
    Vec3 dir;
    for (uint64_t x : v) {
      if (values_[x] < 0) {
        in[n_in++] = x;
      } else {
        outside[n_out++] = x;
      }
    }
    if (n_in == 0 || n_out == 0) return;
    for (int k = 0; k < n_out; ++k) dir += g_.point(outside[k]) / n_out;
    for (int k = 0; k < n_in; ++k) dir -= g_.point(in[k]) / n_in;
    if (n_in == 1) {
      triangle(cut(in[0], outside[0]), cut(in[0], outside[1]), cut(in[0], outside[2]), dir);
    } else if (n_in == 3) {
      triangle(cut(in[0], outside[0]), cut(in[1], outside[0]), cut(in[2], outside[0]), dir);
    } else {
      const uint32_t q[4] = {cut(in[0], outside[0]), cut(in[0], outside[1]), cut(in[1], outside[1]),
                             cut(in[1], outside[0])};
      const auto& p = out_.positions;
      if (squared_norm(p[q[0]] - p[q[2]]) <= squared_norm(p[q[1]] - p[q[3]])) {
        triangle(q[0], q[1], q[2], dir);
        triangle(q[0], q[2], q[3], dir);
      } else {
        triangle(q[0], q[1], q[3], dir);
        triangle(q[1], q[2], q[3], dir);
      }
    }
  }

 private:
  uint32_t cut(uint64_t inside, uint64_t outside) {
    const uint64_t key = std::min(inside, outside) * 0x100000000ull + std::max(inside, outside);
    auto [it, inserted] = ids_.try_emplace(key, uint32_t(out_.positions.size()));
    if (inserted) {
      const double a = values_[inside], b = values_[outside];
      const double t = std::clamp(a / (a - b), kCutClamp, 1 - kCutClamp);
      const Vec3 p = g_.point(inside);
      out_.positions.push_back(p + t * (g_.point(outside) - p));
    }
    return it->second;
  }
  void triangle(uint32_t a, uint32_t b, uint32_t c, Vec3 dir) {
    const auto& p = out_.positions;
    if (dot(cross(p[b] - p[a], p[c] - p[a]), dir) < 0) std::swap(b, c);
    out_.add_face({a, b, c});
  }

  const Grid& g_;
  const std::vector<double>& values_;
  PolyMesh& out_;
  std::unordered_map<uint64_t, uint32_t> ids_;
};

// Each vertex a step towards the mean of its neighbours, then back onto the zero set by Newton
// steps along the gradient (central differences): the cuts near grid vertices spread out.
void relax_onto(PolyMesh& m, const Implicit& f, double h, int rounds) {
  std::vector<std::vector<uint32_t>> ring(m.num_vertices());
  for (std::size_t t = 0; t < m.num_faces(); ++t) {
    const auto v = m.face(t);
    for (int k = 0; k < 3; ++k) ring[v[k]].push_back(v[(k + 1) % 3]);
  }
  const double e = 1e-3 * h;
  for (int r = 0; r < rounds; ++r) {
    std::vector<Vec3> next = m.positions;
    for (std::size_t v = 0; v < next.size(); ++v) {
      Vec3 mean;
      for (uint32_t w : ring[v]) mean += m.positions[w] / double(ring[v].size());
      Vec3 p = 0.5 * (m.positions[v] + mean);
      for (int step = 0; step < 3; ++step) {
        const Vec3 g = Vec3{f(p + Vec3{e, 0, 0}) - f(p - Vec3{e, 0, 0}),
                            f(p + Vec3{0, e, 0}) - f(p - Vec3{0, e, 0}),
                            f(p + Vec3{0, 0, e}) - f(p - Vec3{0, 0, e})} /
                       (2 * e);
        const double g2 = squared_norm(g);
        if (g2 < 1e-12) break;
        const Vec3 move = f(p) / g2 * g;
        // A Newton step longer than a cell would leave the surface's neighbourhood.
        if (squared_norm(move) > h * h) break;
        p -= move;
      }
      next[v] = p;
    }
    m.positions = std::move(next);
  }
}

}  // namespace

PolyMesh marching_tets(const Implicit& f, Vec3 lo, Vec3 hi, double h, int smoothing_rounds) {
  Grid g{lo, h, int(std::ceil((hi.x - lo.x) / h)) + 1, int(std::ceil((hi.y - lo.y) / h)) + 1,
         int(std::ceil((hi.z - lo.z) / h)) + 1};
  std::vector<double> values(uint64_t(g.nx) * g.ny * g.nz);
  for (uint64_t v = 0; v < values.size(); ++v) {
    values[v] = f(g.point(v));
    if (values[v] == 0) values[v] = 1e-12 * h;  // no vertex on the surface: a generic level set
  }
  PolyMesh m;
  TetCutter cutter(g, values, m);
  // The six Kuhn tetrahedra: from corner 0 to corner 7 one axis at a time, in each order.
  constexpr int kOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k + 1 < g.nz; ++k)
    for (int j = 0; j + 1 < g.ny; ++j)
      for (int i = 0; i + 1 < g.nx; ++i) {
        auto corner = [&](int bits) {
          return g.id(i + (bits & 1), j + ((bits >> 1) & 1), k + ((bits >> 2) & 1));
        };
        for (const auto& o : kOrders) {
          const int a = 1 << o[0], b = a | (1 << o[1]);
          cutter.tet({corner(0), corner(a), corner(b), corner(7)});
        }
      }
  m = largest_component(m);
  relax_onto(m, f, h, smoothing_rounds);
  return m;
}

PolyMesh largest_component(const PolyMesh& m) {
  std::vector<uint32_t> parent(m.num_vertices());
  std::iota(parent.begin(), parent.end(), 0u);
  auto root = [&](uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (std::size_t t = 0; t < m.num_faces(); ++t) {
    const auto v = m.face(t);
    for (std::size_t k = 1; k < v.size(); ++k) parent[root(v[k])] = root(v[0]);
  }
  std::vector<uint32_t> faces_of(m.num_vertices(), 0);
  for (std::size_t t = 0; t < m.num_faces(); ++t) ++faces_of[root(m.face(t)[0])];
  const uint32_t keep =
      uint32_t(std::max_element(faces_of.begin(), faces_of.end()) - faces_of.begin());
  PolyMesh out;
  std::vector<uint32_t> id(m.num_vertices(), UINT32_MAX);
  for (std::size_t t = 0; t < m.num_faces(); ++t) {
    const auto v = m.face(t);
    if (root(v[0]) != keep) continue;
    std::vector<uint32_t> f;
    for (uint32_t x : v) {
      if (id[x] == UINT32_MAX) {
        id[x] = uint32_t(out.positions.size());
        out.positions.push_back(m.positions[x]);
      }
      f.push_back(id[x]);
    }
    out.add_face(f);
  }
  return out;
}

}  // namespace isoquad::test
