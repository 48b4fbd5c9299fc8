// Between the library's PolyMesh and the public plain arrays (isoquad/io.hpp): one conversion
// each way, shared by the array readers and writers and by remesh(V, F).
#pragma once

#include <Eigen/Core>

#include "core/poly_mesh.hpp"

namespace isoquad {

// Rows of F end at their first -1 (so a #F x 3 matrix is a triangle mesh).
// \throw Error(invalid_input, E020) V not #V x 3, F with fewer than 3 columns, an index out of
//        range, or a row with fewer than 3 indices before its first -1.
PolyMesh poly_mesh_from_arrays(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// F is #F x k, k the largest face size, shorter faces padded with -1.
void arrays_from_poly_mesh(const PolyMesh& mesh, Eigen::MatrixXd& V, Eigen::MatrixXi& F);

}  // namespace isoquad
