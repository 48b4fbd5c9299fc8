// The generated stress set of issue 32: 104 triangle meshes in 8 families of 13 (tori of genus
// 1 to 5, thin tubes, noisy spheres, plates with holes, boxes with fillets, pipes with branches,
// twisted strips with boundary, scanned-like bumpy blobs), 2k to 30k triangles each. Every shape
// depends on its parameters only (fixed seeds, no file, no clock): implicit ones are polygonised
// by marching_tets.hpp, the others are parametric. Each builder's topology is the intended one
// by construction, and build_stress_mesh checks it.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/poly_mesh.hpp"

namespace isoquad::test {

struct StressCase {
  std::string family;  // tori, tubes, spheres, plates, boxes, pipes, strips, blobs
  std::string name;    // unique, a test name: family and number (tori_03)
  std::string params;  // what the builder was given, for the tables
  int64_t euler = 2;   // the intended topology (one component)
  uint32_t boundary_loops = 0;
  std::function<PolyMesh()> build;  // at its own size, about 1 to 4 across
};

// Every case, family after family.
const std::vector<StressCase>& stress_cases();

// The subset CI remeshes: 2 of each family, chosen for variety (the first at diagonal 1e-3, the
// second at 1e3).
std::vector<const StressCase*> stress_ci_cases();

// The case's mesh with its topology checked.
// \throw std::logic_error when the mesh is not one manifold, oriented component of the intended
//        Euler characteristic and boundary loops (a bug of the generator).
PolyMesh build_stress_mesh(const StressCase& c);

// `m` moved to the origin and scaled to the bounding-box diagonal `diagonal`.
PolyMesh scaled_to_diagonal(PolyMesh m, double diagonal);

}  // namespace isoquad::test
