// Transition between two charts (paper §2: "jump" and "rotation"): p' = R^k p + t with R the
// CCW quarter turn, k in {0,1,2,3} and t an integer vector. Exact integer arithmetic.
#pragma once

#include <array>
#include <cstdint>

namespace isoquad {

using Lattice = std::array<int64_t, 2>;

inline Lattice rotate(Lattice p, int k) {
  switch (((k % 4) + 4) % 4) {
    case 1:
      return {-p[1], p[0]};
    case 2:
      return {-p[0], -p[1]};
    case 3:
      return {p[1], -p[0]};
    default:
      return p;
  }
}

struct Transition {
  int k = 0;        // quarter turns, 0..3
  Lattice t{0, 0};  // jump

  Lattice apply(Lattice p) const {
    const Lattice r = rotate(p, k);
    return {r[0] + t[0], r[1] + t[1]};
  }
  // Rotation part only (for directions).
  Lattice rotate_only(Lattice d) const { return rotate(d, k); }
  Transition inverse() const {  // p = R^-k (p' - t)
    const Lattice r = rotate({-t[0], -t[1]}, 4 - k);
    return {(4 - k) % 4, r};
  }
  // (this * other)(p) = this(other(p)).
  Transition operator*(const Transition& o) const {
    const Lattice r = rotate(o.t, k);
    return {(k + o.k) % 4, {r[0] + t[0], r[1] + t[1]}};
  }
  friend bool operator==(const Transition&, const Transition&) = default;
};

}  // namespace isoquad
