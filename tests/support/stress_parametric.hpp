// The parametric builders of the stress set (stress_shapes.hpp): swept tubes, grid surfaces
// (ribbons and bands) and flat plates with round holes.
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "core/poly_mesh.hpp"

namespace isoquad::test {

// A tube of `radius` around curve(t), t in [0, 1], on parallel-transported frames: closed (the
// frames' turn after a loop spread along it; curve(1) = curve(0)) or capped with half spheres.
// `n_around` vertices a ring, rings `aspect` times as far apart as the ring's vertices.
// \throw std::logic_error when parts of the curve farther apart along it than 3 radii come closer
// than 2.2 radii: the tube would cut itself.
PolyMesh swept_tube(const std::function<Vec3(double)>& curve, bool closed, double radius,
                    int n_around, double aspect);

// The grid p(u, v), u and v in [0, 1], nu x nv cells of two triangles; closed in u (p(1, v) =
// p(0, v)) or open.
PolyMesh grid_surface(int nu, int nv, bool closed_u, const std::function<Vec3(double, double)>& p);

// The rectangle [0, a] x [0, b] at z = 0 without the disks (x, y, r), triangulated on a grid of
// step h cut along the circles (marching triangles).
// \pre the disks are apart from one another and from the sides by more than 2 h.
PolyMesh plate_with_holes(double a, double b, const std::vector<std::array<double, 3>>& holes,
                          double h);

}  // namespace isoquad::test
