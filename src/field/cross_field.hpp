// A smooth 4-direction (cross) field on a triangle mesh, one cross per face (FIELD_LAYOUT.md
// §1-§2; Knoeppel, Crane, Pinkall and Schroeder 2013): hard-aligned to feature edges and the
// boundary, softly to the principal curvature directions where the surface is clearly
// anisotropic, smooth elsewhere; then its period jumps and its singularities (index k/4 at
// vertices). One global, deterministic solve.
#pragma once

#include <complex>
#include <cstdint>
#include <vector>

#include "core/element_data.hpp"
#include "core/refined_mesh.hpp"
#include "core/tri_mesh.hpp"
#include "field/face_frames.hpp"

namespace isoquad {

struct CrossFieldOptions {
  // h, the target quad edge length (mesh units): the scale below which curvature is not
  // followed. 0: no curvature guidance.
  double edge_length = 0;
  // The field follows curvature varying over more than this many h (lambda = 1 / (scale h)^2).
  double guidance_scale = 2;
  bool curvature = true;
  // Re-solves towards the unit-length field, removing the smoothest field's bias to small |u|
  // near singularities (constraints kept).
  uint32_t normalize_rounds = 1;
  // The field is solved on a copy of the surface smoothed at the scale of h (Ebke et al. 2014:
  // the field should not see detail finer than a quad, whose curvature only breeds +- pairs of
  // singularities): one implicit mean curvature flow step of time smoothing * h^2, feature and
  // boundary vertices fixed. 0: off. Its effect on the corpus's singularities is in
  // docs/field.md.
  double smoothing = 1;
  // Feature networks shorter than this many h in all neither constrain the field nor hold their
  // vertices while smoothing (long_features in feature_curves.hpp).
  double min_feature_length = 2;
  // Nor do networks shorter than weak_feature_length h whose mean dihedral angle is below
  // weak_feature_angle degrees: the creases an organic mesh shows at the feature angle, each of
  // which pinned the field and bred singularities. Their effect on the corpus is in
  // docs/field.md.
  double weak_feature_length = 10, weak_feature_angle = 80;
};

enum class FieldVariant {
  linear,  // constraints or curvature guidance: one linear solve
  eigen,   // nothing pins the field: the smoothest unit field, by inverse iteration
};

struct CrossField {
  // The surface the field lives on: the input's connectivity (same vertex, face and halfedge
  // ids) at the smoothed positions (CrossFieldOptions::smoothing), or the input itself. Frames,
  // angles and traces are in its geometry; a trace, being a sequence of edge points, carries over
  // to the input by the same edge fractions.
  TriMesh surface;
  FaceFrames frames;
  FaceData<double> angle;       // theta_f in [0, pi/2), in f's frame
  FaceData<double> confidence;  // |u_f| before normalization (1 where constrained)
  FaceData<char> constrained;   // aligned to a feature or boundary edge
  EdgeData<char> feature;       // the feature edges the field is aligned to (long curves only)
  uint32_t short_feature_networks = 0;  // feature networks left out of the constraints
  // Period jump of halfedge h (face f, twin in g): direction k of f continues as k + p (mod 4)
  // in g. The twin has -p; 0 on the boundary.
  HalfedgeData<int8_t> period_jump;
  // 4 I_v: 0 at a regular interior vertex, +1 at a valence-3-like singularity, -1 at a
  // valence-5-like one. At a boundary vertex, 4 I_v = 2 - q_v with q_v the quads the field
  // puts there (2 on a straight stretch, 1 at a convex corner, 3 at a concave one).
  VertexData<int32_t> index4;
  // Vertices where the field is singular: interior ones with index4 != 0, boundary ones whose
  // q_v differs from what their angle asks (max(1, round(angle / 90 degrees))).
  std::vector<uint32_t> singular;
  FieldVariant variant = FieldVariant::linear;
  uint32_t constrained_faces = 0;
  uint32_t solves = 0;
  double guided_area_share = 0;  // share of the area with curvature weight > 0.5
  double energy = 0;             // smoothness energy sum_e w_e |u_g - r_fg u_f|^2 of the unit field

  // The unit 3D direction k (0..3) of the cross of face f, on `surface`.
  Vec3 direction(uint32_t f, int k) const;
  // The same direction on another geometry of the same connectivity (the input, when the field
  // was solved on a smoothed copy): the same combination of face f's edge vectors, normalized.
  Vec3 direction_on(const TriMesh& mesh, uint32_t f, int k) const;
};

// Faces with two feature or boundary edges that disagree by more than 10 degrees (mod 90) cannot
// be aligned with both (FIELD_LAYOUT.md §1): each gets its third edge split, so that every piece
// holds one of them. Repeats until no such face is left (at most `rounds` times); `feature`
// follows the refinement. A face whose three edges are all constrained stays as it is.
RefinedMesh split_constraint_conflicts(const RefinedMesh& in, EdgeData<char>& feature,
                                       uint32_t rounds = 3);

// \throw Error(solver, E561) if the field's system cannot be factorized or gives non-finite
//        values; Error(internal, E700) if the indices break Poincare-Hopf (sum I_v = chi).
CrossField compute_cross_field(const TriMesh& mesh, const EdgeData<char>& feature,
                               const CrossFieldOptions& options);

}  // namespace isoquad
