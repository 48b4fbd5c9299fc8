// Exact 2D orientation (DESIGN.md §7.7): the sign of det[b - a, c - a] computed exactly for any
// double inputs, with a floating-point filter that decides almost every call and an exact
// expansion sum for the rest. Used to certify that no triangle of a map is flipped.
#pragma once

#include <array>

namespace isoquad {

using UV = std::array<double, 2>;

// Positive when a, b, c turn counter-clockwise, negative when clockwise, zero when collinear.
// The sign is exact; the magnitude is an approximation of twice the signed area.
double orient2d(const UV& a, const UV& b, const UV& c);

}  // namespace isoquad
