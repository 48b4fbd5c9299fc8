// Tangent frames of the faces and the discrete Levi-Civita connection between neighbouring
// faces (FIELD_LAYOUT.md §1): the common language of the cross field, its singularities and the
// tracing. An angle in face f is measured from x_f towards y_f = n_f x x_f.
#pragma once

#include "core/element_data.hpp"
#include "core/tri_mesh.hpp"

namespace isoquad {

struct FaceFrames {
  FaceData<Vec3> x, y, normal;
  // For halfedge h in face f whose twin lies in g: rho = arg_g(d) - arg_f(d) for the shared
  // edge vector d, wrapped to (-pi, pi]. An angle t in f is t + rho in g (unfolding); 0 on the
  // boundary.
  HalfedgeData<double> rho;
  // The angle of a vector in f's tangent plane (its normal component ignored).
  double arg(uint32_t f, Vec3 d) const;
  // The unit vector at angle t in f's tangent plane.
  Vec3 direction(uint32_t f, double t) const;
};

// x_f along the face's first edge; a degenerate face (zero area) takes its longest edge and a
// normal perpendicular to it, so that every frame is orthonormal.
FaceFrames face_frames(const TriMesh& mesh);

// Wraps an angle to (-period/2, period/2].
double wrap_angle(double a, double period);

}  // namespace isoquad
