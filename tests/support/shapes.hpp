// Synthetic shapes for unit tests, built in code (no data files). All closed shapes are
// oriented outward.
#pragma once

#include "core/poly_mesh.hpp"

namespace isoquad::test {

PolyMesh icosphere(int subdivisions);               // chi = 2
PolyMesh torus(int n_major, int n_minor);           // chi = 0, triangles
PolyMesh cube_quads();                              // 8 vertices, 6 quads
PolyMesh subdivided_cube(int n);                    // each face an n x n grid of triangle pairs
PolyMesh plate_with_hole(int n);                    // square with a square hole, 2 boundary loops
PolyMesh grid_plate(int nx, int ny);                // open square, one boundary loop
PolyMesh open_cylinder(int n_around, int n_along);  // two boundary loops
PolyMesh mobius_strip(int n);                       // non-orientable, one boundary loop
PolyMesh stl_soup(const PolyMesh& triangles);       // every triangle with its own 3 vertices

}  // namespace isoquad::test
