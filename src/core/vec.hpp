// Small fixed-size vectors for positions and directions. Eigen stays in .cpp files that
// solve systems; geometry code that only needs +, -, dot and cross uses these.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace isoquad {

struct Vec3 {
  double x = 0, y = 0, z = 0;
  double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  friend bool operator==(const Vec3&, const Vec3&) = default;
};

inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
inline Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline Vec3 operator*(Vec3 a, double s) { return s * a; }
inline Vec3 operator/(Vec3 a, double s) { return {a.x / s, a.y / s, a.z / s}; }
inline Vec3& operator+=(Vec3& a, Vec3 b) { return a = a + b; }
inline Vec3& operator-=(Vec3& a, Vec3 b) { return a = a - b; }
inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double squared_norm(Vec3 a) { return dot(a, a); }
inline double norm(Vec3 a) { return std::sqrt(dot(a, a)); }
// The angle between a and b in [0, pi], accurate near 0 and pi (unlike acos of the cosine).
inline double angle_between(Vec3 a, Vec3 b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }
inline Vec3 normalized(Vec3 a) {
  const double n = norm(a);
  return n > 0 ? a / n : Vec3{};
}
inline bool is_finite(Vec3 a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}
// a times 2^k: exact while the result stays in the normal range.
inline Vec3 ldexp(Vec3 a, int k) {
  return {std::ldexp(a.x, k), std::ldexp(a.y, k), std::ldexp(a.z, k)};
}
// |a| without overflow or underflow in the squares (1e154 and 1e-162 are where dot(a, a) ends):
// a is first scaled by a power of two, exactly, so the bits are norm(a)'s wherever that is
// finite and nonzero. Infinite only where |a| itself is beyond the largest double.
inline double scaled_norm(Vec3 a) {
  const double m = std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)});
  if (!(m > 0) || !std::isfinite(m)) return m;  // 0, inf or NaN
  const int k = std::ilogb(m);
  return std::ldexp(norm(ldexp(a, -k)), k);
}
// The least k with every finite |coordinate| below 2^k (0 without a nonzero one). Coordinates
// scaled by 2^-k are below 1, and their squares and cross products neither overflow nor
// underflow.
inline int magnitude_exponent(const std::vector<Vec3>& points) {
  double m = 0;
  for (const Vec3& p : points)
    for (int i = 0; i < 3; ++i)
      if (std::isfinite(p[i])) m = std::max(m, std::fabs(p[i]));
  int k = 0;
  if (m > 0) std::frexp(m, &k);
  return k;
}
// Coordinates within 2^±kSafeExponent keep products of up to four of them in the normal range;
// code that multiplies coordinates scales meshes beyond it by 2^-magnitude_exponent first.
constexpr int kSafeExponent = 128;

// Axis-aligned bounding box; empty until the first point is added.
struct Box3 {
  Vec3 lo{INFINITY, INFINITY, INFINITY};
  Vec3 hi{-INFINITY, -INFINITY, -INFINITY};
  // As std::fmin and std::fmax (a NaN coordinate is ignored: the bounds are never NaN), but
  // inlined to minsd/maxsd instead of libm calls: 2% of a bunny00 remesh in AabbTree::build.
  void add(Vec3 p) {
    for (int i = 0; i < 3; ++i) {
      lo[i] = p[i] < lo[i] ? p[i] : lo[i];
      hi[i] = p[i] > hi[i] ? p[i] : hi[i];
    }
  }
  bool empty() const { return lo.x > hi.x; }
  // Halves first, so neither overflows for any finite bounds (the same bits as 0.5 * (lo + hi)
  // and norm(hi - lo) where those are finite).
  Vec3 center() const { return 0.5 * lo + 0.5 * hi; }
  double diagonal() const { return empty() ? 0.0 : 2 * scaled_norm(0.5 * hi - 0.5 * lo); }
};

}  // namespace isoquad
