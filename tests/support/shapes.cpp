#include "shapes.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

namespace isoquad::test {

namespace {
constexpr double kPi = std::numbers::pi;
}

PolyMesh icosphere(int subdivisions) {
  PolyMesh m;
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  const Vec3 base[12] = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (const Vec3& p : base) m.positions.push_back(normalized(p));
  std::vector<std::array<uint32_t, 3>> faces = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.positions.push_back(normalized(m.positions[a] + m.positions[b]));
      return mid[key] = uint32_t(m.positions.size() - 1);
    };
    std::vector<std::array<uint32_t, 3>> next;
    for (const auto& f : faces) {
      const uint32_t a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      next.insert(next.end(), {{f[0], a, c}, {f[1], b, a}, {f[2], c, b}, {a, b, c}});
    }
    faces = std::move(next);
  }
  for (const auto& f : faces) m.add_face({f[0], f[1], f[2]});
  return m;
}

PolyMesh torus(int n_major, int n_minor) {
  PolyMesh m;
  const double R = 1.0, r = 0.35;
  for (int i = 0; i < n_major; ++i)
    for (int j = 0; j < n_minor; ++j) {
      const double u = 2 * kPi * i / n_major, v = 2 * kPi * j / n_minor;
      m.positions.push_back({(R + r * std::cos(v)) * std::cos(u),
                             (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
    }
  auto id = [&](int i, int j) { return uint32_t((i % n_major) * n_minor + (j % n_minor)); };
  for (int i = 0; i < n_major; ++i)
    for (int j = 0; j < n_minor; ++j) {
      m.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.add_face({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

PolyMesh cube_quads() {
  PolyMesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.push_back({double(i & 1), double((i >> 1) & 1), double(i >> 2)});
  m.add_face({0, 2, 3, 1});  // z = 0, normal -z
  m.add_face({4, 5, 7, 6});  // z = 1
  m.add_face({0, 1, 5, 4});  // y = 0
  m.add_face({2, 6, 7, 3});  // y = 1
  m.add_face({0, 4, 6, 2});  // x = 0
  m.add_face({1, 3, 7, 5});  // x = 1
  return m;
}

PolyMesh subdivided_cube(int n) {
  PolyMesh m;
  std::map<std::array<int, 3>, uint32_t> ids;  // shared lattice points on cube edges
  auto id = [&](std::array<int, 3> g) {
    auto [it, inserted] = ids.try_emplace(g, uint32_t(m.positions.size()));
    if (inserted) m.positions.push_back({double(g[0]) / n, double(g[1]) / n, double(g[2]) / n});
    return it->second;
  };
  // For each face: the fixed axis, its value, and two in-plane axes ordered for an outward normal.
  const int faces[6][4] = {{0, 0, 2, 1}, {0, 1, 1, 2}, {1, 0, 0, 2},
                           {1, 1, 2, 0}, {2, 0, 1, 0}, {2, 1, 0, 1}};
  for (const auto& f : faces) {
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        auto g = [&](int a, int b) {
          std::array<int, 3> p{};
          p[f[0]] = f[1] * n;
          p[f[2]] = a;
          p[f[3]] = b;
          return id(p);
        };
        m.add_face({g(i, j), g(i + 1, j), g(i + 1, j + 1)});
        m.add_face({g(i, j), g(i + 1, j + 1), g(i, j + 1)});
      }
  }
  return m;
}

PolyMesh plate_with_hole(int n) {
  PolyMesh m = grid_plate(n, n);
  PolyMesh out;
  out.positions = m.positions;
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    Vec3 c;
    for (uint32_t v : m.face(f)) c += m.positions[v] / 3.0;
    if (std::fabs(c.x - 0.5) < 0.2 && std::fabs(c.y - 0.5) < 0.2) continue;
    out.add_face(m.face(f));
  }
  return out;
}

PolyMesh grid_plate(int nx, int ny) {
  PolyMesh m;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.positions.push_back({double(i) / nx, double(j) / ny, 0});
  auto id = [&](int i, int j) { return uint32_t(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      m.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.add_face({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

PolyMesh open_cylinder(int n_around, int n_along) {
  PolyMesh m;
  for (int j = 0; j <= n_along; ++j)
    for (int i = 0; i < n_around; ++i) {
      const double a = 2 * kPi * i / n_around;
      m.positions.push_back({std::cos(a), std::sin(a), 3.0 * j / n_along});
    }
  auto id = [&](int i, int j) { return uint32_t(j * n_around + (i % n_around)); };
  for (int j = 0; j < n_along; ++j)
    for (int i = 0; i < n_around; ++i) {
      m.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.add_face({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

PolyMesh mobius_strip(int n) {
  PolyMesh m;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * kPi * i / n;
    for (int s = -1; s <= 1; s += 2) {
      const double w = 0.3 * s;
      m.positions.push_back({(1 + w * std::cos(a / 2)) * std::cos(a),
                             (1 + w * std::cos(a / 2)) * std::sin(a), w * std::sin(a / 2)});
    }
  }
  for (int i = 0; i < n; ++i) {
    const uint32_t a0 = 2 * i, a1 = 2 * i + 1;
    // After a full turn the strip comes back with its two sides swapped.
    const bool last = i == n - 1;
    const uint32_t b0 = last ? 1 : 2 * (i + 1), b1 = last ? 0 : 2 * (i + 1) + 1;
    m.add_face({a0, b0, b1});
    m.add_face({a0, b1, a1});
  }
  return m;
}

PolyMesh stl_soup(const PolyMesh& tri) {
  PolyMesh m;
  for (std::size_t f = 0; f < tri.num_faces(); ++f) {
    const uint32_t base = uint32_t(m.positions.size());
    for (uint32_t v : tri.face(f)) m.positions.push_back(tri.positions[v]);
    m.add_face({base, base + 1, base + 2});
  }
  return m;
}

}  // namespace isoquad::test
