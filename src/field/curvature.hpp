// Soft alignment targets for the cross field from the surface's curvature (FIELD_LAYOUT.md §1,
// "Guidance"): where the surface bends clearly more one way than the other over about one quad,
// the cross should follow the principal directions; where it is umbilic, flat or near a hard
// constraint, curvature says nothing.
#pragma once

#include <complex>

#include "core/element_data.hpp"
#include "core/tri_mesh.hpp"
#include "field/face_frames.hpp"

namespace isoquad {

struct CurvatureGuidance {
  // q_f = e^{4i phi_f}, phi_f a principal direction in f's frame; 0 where there is none.
  FaceData<std::complex<double>> target;
  // a_f in [0, 1): s^2 / (s^2 + 0.01) with s = h |k1 - k2|, faded to 0 within 2h of a feature or
  // boundary edge so that curvature noise does not fight a crease.
  FaceData<double> weight;
};

// The anisotropic part of the edge-based shape operator (sum of signed dihedral angle times
// length times the edge's direction squared, Cohen-Steiner and Morvan), averaged over a radius of
// about h with parallel transport. `h` in mesh units, > 0.
CurvatureGuidance curvature_guidance(const TriMesh& mesh, const FaceFrames& frames,
                                     const EdgeData<char>& feature, double h);

}  // namespace isoquad
