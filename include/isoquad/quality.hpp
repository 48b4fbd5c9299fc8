// Quality of a quad mesh, as `isoquad quality --json` prints it: validity (pure quad, manifold,
// oriented, topology against the input), singularities, element shape (scaled Jacobian, angles,
// edge lengths) and the two-sided distance to the input surface over its bounding-box diagonal.
#pragma once

#include <Eigen/Core>
#include <string>

namespace isoquad {

// V #V x 3; F #F x k, rows ending at their first -1 (as isoquad/io.hpp reads them). With a
// reference (the input triangles, or polygons), also the topology comparison, the scaled
// Jacobians against the reference's normals and the distances.
// \pre F has at least one face.
// \throw Error(invalid_input, E020) wrong shapes or an index out of range.
std::string quality_json(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                         const Eigen::MatrixXd* reference_V = nullptr,
                         const Eigen::MatrixXi* reference_F = nullptr);

}  // namespace isoquad
