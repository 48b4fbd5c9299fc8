// Small fixed-size vectors for positions and directions. Eigen stays in .cpp files that
// solve systems; geometry code that only needs +, -, dot and cross uses these.
#pragma once

#include <cmath>

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
  Vec3 center() const { return 0.5 * (lo + hi); }
  double diagonal() const { return empty() ? 0.0 : norm(hi - lo); }
};

}  // namespace isoquad
