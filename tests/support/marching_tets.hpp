// Triangle meshes of implicit surfaces for the generated stress set (stress_shapes.hpp): marching
// tetrahedra on a grid of cubes, each cut into the six Kuhn tetrahedra, so that neighbouring
// cubes agree on their faces and the zero set of the piecewise linear function is a closed
// 2-manifold (no grid value is left at 0). Then the mesh is cleaned for a remesher: its largest
// component kept, and slivers (the cuts near grid vertices) relaxed by Laplacian steps projected
// back onto the zero set.
#pragma once

#include <functional>

#include "core/poly_mesh.hpp"

namespace isoquad::test {

// Negative inside; a signed distance or near one (the projection divides by the gradient).
using Implicit = std::function<double(const Vec3&)>;

// The zero set of `f` within [lo, hi] on cubes of side `h`, oriented outward (towards f > 0).
// \pre f > 0 on the box's boundary, so that the surface is closed.
PolyMesh marching_tets(const Implicit& f, Vec3 lo, Vec3 hi, double h, int smoothing_rounds = 3);

// The faces of the largest connected component (by faces), its vertices renumbered.
PolyMesh largest_component(const PolyMesh& m);

}  // namespace isoquad::test
