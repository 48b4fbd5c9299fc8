#include "core/predicates.hpp"

#include <cmath>
#include <limits>

namespace isoquad {

namespace {

// a + b = s + e exactly (Knuth's two-sum).
inline void two_sum(double a, double b, double& s, double& e) {
  s = a + b;
  const double bb = s - a;
  e = (a - (s - bb)) + (b - bb);
}

// Exact sign of a sum of doubles: the terms are accumulated into a non-overlapping expansion
// (each new term is swept through the components with two-sum), whose most significant
// non-zero component carries the sign of the exact sum.
double exact_sign_of_sum(const double* terms, int n) {
  double expansion[32];
  int m = 0;
  for (int i = 0; i < n; ++i) {
    double q = terms[i];
    for (int j = 0; j < m; ++j) {
      double s, e;
      two_sum(q, expansion[j], s, e);
      expansion[j] = e;
      q = s;
    }
    expansion[m++] = q;
  }
  for (int j = m - 1; j >= 0; --j)
    if (expansion[j] != 0) return expansion[j] > 0 ? 1.0 : -1.0;
  return 0.0;
}

}  // namespace

double orient2d(const UV& a, const UV& b, const UV& c) {
  const double l = (a[0] - c[0]) * (b[1] - c[1]);
  const double r = (a[1] - c[1]) * (b[0] - c[0]);
  const double det = l - r;
  // Shewchuk's first-stage bound: |det - exact| <= (3 + 16 eps) eps (|l| + |r|).
  constexpr double eps = std::numeric_limits<double>::epsilon() / 2;
  constexpr double bound = (3.0 + 16.0 * eps) * eps;
  if (std::fabs(det) > bound * (std::fabs(l) + std::fabs(r))) return det;
  // Exact: det = ax by - ax cy - cx by - ay bx + ay cx + cy bx (the cx cy terms cancel); each
  // product is split into its rounded value and its exact error with a fused multiply-add.
  const double f[6][2] = {{a[0], b[1]},  {-a[0], c[1]}, {-c[0], b[1]},
                          {-a[1], b[0]}, {a[1], c[0]},  {c[1], b[0]}};
  double terms[12];
  for (int i = 0; i < 6; ++i) {
    const double p = f[i][0] * f[i][1];
    terms[2 * i] = p;
    terms[2 * i + 1] = std::fma(f[i][0], f[i][1], -p);
  }
  const double sign = exact_sign_of_sum(terms, 12);
  if (sign == 0) return 0.0;
  // Keep the sign exact while returning a magnitude of the right order.
  const double mag = std::fabs(det) > 0 ? std::fabs(det) : std::numeric_limits<double>::min();
  return sign * mag;
}

}  // namespace isoquad
