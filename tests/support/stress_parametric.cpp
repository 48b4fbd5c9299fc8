#include "stress_parametric.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <unordered_map>

#include "marching_tets.hpp"

namespace isoquad::test {

namespace {

constexpr double kPi = std::numbers::pi;

// n + 1 points of the curve evenly spaced by arc length (from 4,096 chords).
std::vector<Vec3> resample(const std::function<Vec3(double)>& curve, int n, double& length) {
  constexpr int kFine = 4096;
  std::vector<Vec3> fine(kFine + 1);
  std::vector<double> s(kFine + 1, 0);
  for (int i = 0; i <= kFine; ++i) {
    fine[i] = curve(double(i) / kFine);
    if (i > 0) s[i] = s[i - 1] + norm(fine[i] - fine[i - 1]);
  }
  length = s[kFine];
  if (n == 0) return {};
  std::vector<Vec3> out(n + 1);
  int j = 0;
  for (int i = 0; i <= n; ++i) {
    const double target = length * i / n;
    while (j + 1 < kFine && s[j + 1] < target) ++j;
    const double t = std::clamp((target - s[j]) / (s[j + 1] - s[j]), 0.0, 1.0);
    out[i] = fine[j] + t * (fine[j + 1] - fine[j]);
  }
  return out;
}

void check_no_self_approach(const std::vector<Vec3>& c, bool closed, double step, double radius) {
  const std::size_t n = c.size();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const std::size_t apart = closed ? std::min(j - i, n - (j - i)) : j - i;
      if (double(apart) * step > 3 * radius && norm(c[i] - c[j]) < 2.2 * radius)
        throw std::logic_error("swept_tube: the tube cuts itself");
    }
}

// Flips every face when the signed volume is negative (closed meshes: outward).
void orient_outward(PolyMesh& m) {
  double volume = 0;
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    const auto v = m.face(f);
    volume += dot(m.positions[v[0]], cross(m.positions[v[1]], m.positions[v[2]]));
  }
  if (volume >= 0) return;
  for (std::size_t f = 0; f < m.num_faces(); ++f)
    std::reverse(m.face_vertices.begin() + m.face_offsets[f],
                 m.face_vertices.begin() + m.face_offsets[f + 1]);
}

}  // namespace

PolyMesh swept_tube(const std::function<Vec3(double)>& curve, bool closed, double radius,
                    int n_around, double aspect) {
  double length = 0;
  resample(curve, 0, length);
  const int n = std::max(8, int(std::lround(length / (aspect * 2 * kPi * radius / n_around))));
  std::vector<Vec3> c = resample(curve, n, length);
  if (closed) c.pop_back();
  const int count = int(c.size());
  check_no_self_approach(c, closed, length / n, radius);
  std::vector<Vec3> t(count), nrm(count);
  for (int i = 0; i < count; ++i) {
    const int prev = closed ? (i + count - 1) % count : std::max(i - 1, 0);
    const int next = closed ? (i + 1) % count : std::min(i + 1, count - 1);
    t[i] = normalized(c[next] - c[prev]);
  }
  // Parallel transport by projection; a closed tube's leftover turn is spread along it.
  const Vec3 e = std::fabs(t[0].x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  nrm[0] = normalized(cross(t[0], e));
  for (int i = 1; i < count; ++i) nrm[i] = normalized(nrm[i - 1] - dot(nrm[i - 1], t[i]) * t[i]);
  if (closed) {
    const Vec3 back = normalized(nrm[count - 1] - dot(nrm[count - 1], t[0]) * t[0]);
    const double turn = std::atan2(dot(t[0], cross(back, nrm[0])), dot(back, nrm[0]));
    for (int i = 0; i < count; ++i) {
      const double a = turn * i / count;
      nrm[i] = std::cos(a) * nrm[i] + std::sin(a) * cross(t[i], nrm[i]);
    }
  }
  PolyMesh m;
  std::vector<uint32_t> rings;  // first vertex of each ring, in order along the tube
  auto ring = [&](Vec3 centre, int i, double rho) {
    rings.push_back(uint32_t(m.positions.size()));
    const Vec3 b = cross(t[i], nrm[i]);
    for (int j = 0; j < n_around; ++j) {
      const double a = 2 * kPi * j / n_around;
      m.positions.push_back(centre + rho * (std::cos(a) * nrm[i] + std::sin(a) * b));
    }
  };
  const int cap = std::max(2, n_around / 4);
  if (!closed) {
    m.positions.push_back(c[0] - radius * t[0]);
    for (int k = 1; k < cap; ++k) {
      const double phi = kPi / 2 * k / cap;
      ring(c[0] - radius * std::cos(phi) * t[0], 0, radius * std::sin(phi));
    }
  }
  for (int i = 0; i < count; ++i) ring(c[i], i, radius);
  if (!closed)
    for (int k = cap - 1; k >= 1; --k) {
      const double phi = kPi / 2 * k / cap;
      ring(c[count - 1] + radius * std::cos(phi) * t[count - 1], count - 1, radius * std::sin(phi));
    }
  const uint32_t na = uint32_t(n_around);
  auto join = [&](uint32_t a, uint32_t b) {
    for (uint32_t j = 0; j < na; ++j) {
      const uint32_t k = (j + 1) % na;
      m.add_face({a + j, a + k, b + k});
      m.add_face({a + j, b + k, b + j});
    }
  };
  for (std::size_t r = 0; r + 1 < rings.size(); ++r) join(rings[r], rings[r + 1]);
  if (closed) {
    join(rings.back(), rings.front());
  } else {
    const uint32_t end = uint32_t(m.positions.size());
    m.positions.push_back(c[count - 1] + radius * t[count - 1]);
    for (uint32_t j = 0; j < na; ++j) {
      m.add_face({0, rings.front() + (j + 1) % na, rings.front() + j});
      m.add_face({end, rings.back() + j, rings.back() + (j + 1) % na});
    }
  }
  orient_outward(m);
  return m;
}

PolyMesh grid_surface(int nu, int nv, bool closed_u, const std::function<Vec3(double, double)>& p) {
  PolyMesh m;
  const int columns = closed_u ? nu : nu + 1;
  for (int i = 0; i < columns; ++i)
    for (int j = 0; j <= nv; ++j) m.positions.push_back(p(double(i) / nu, double(j) / nv));
  auto id = [&](int i, int j) { return uint32_t((i % columns) * (nv + 1) + j); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      if ((i + j) % 2) {
        m.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        m.add_face({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        m.add_face({id(i, j), id(i + 1, j), id(i, j + 1)});
        m.add_face({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  return m;
}

PolyMesh plate_with_holes(double a, double b, const std::vector<std::array<double, 3>>& holes,
                          double h) {
  const int nx = int(std::ceil(a / h)), ny = int(std::ceil(b / h));
  PolyMesh m;
  std::vector<double> g;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const Vec3 p{a * i / nx, b * j / ny, 0};
      double d = INFINITY;
      for (const auto& c : holes) d = std::min(d, std::hypot(p.x - c[0], p.y - c[1]) - c[2]);
      m.positions.push_back(p);
      g.push_back(d == 0 ? 1e-12 * h : d);  // material where positive
    }
  std::unordered_map<uint64_t, uint32_t> cuts;
  auto cut = [&](uint32_t in, uint32_t out) {
    auto [it, inserted] =
        cuts.try_emplace(uint64_t(std::min(in, out)) << 32 | std::max(in, out), 0u);
    if (inserted) {
      const double t = std::clamp(g[in] / (g[in] - g[out]), 0.05, 0.95);
      it->second = uint32_t(m.positions.size());
      m.positions.push_back(m.positions[in] + t * (m.positions[out] - m.positions[in]));
    }
    return it->second;
  };
  PolyMesh out;
  auto emit = [&](uint32_t x, uint32_t y, uint32_t z) {
    const auto& p = m.positions;
    if (cross(p[y] - p[x], p[z] - p[x]).z < 0) std::swap(y, z);
    out.add_face({x, y, z});
  };
  auto triangle = [&](std::array<uint32_t, 3> v) {
    std::array<uint32_t, 3> in{}, outside{};
    int n_in = 0, n_out = 0;
    for (uint32_t x : v) (g[x] > 0 ? in[n_in++] : outside[n_out++]) = x;
    if (n_in == 3) emit(v[0], v[1], v[2]);
    if (n_in == 1) emit(in[0], cut(in[0], outside[0]), cut(in[0], outside[1]));
    if (n_in == 2) {
      const uint32_t c0 = cut(in[0], outside[0]), c1 = cut(in[1], outside[0]);
      emit(in[0], in[1], c1);
      emit(in[0], c1, c0);
    }
  };
  auto id = [&](int i, int j) { return uint32_t(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      if ((i + j) % 2) {
        triangle({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        triangle({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        triangle({id(i, j), id(i + 1, j), id(i, j + 1)});
        triangle({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  out.positions = m.positions;
  return largest_component(out);
}

}  // namespace isoquad::test
