// Feature coverage: how much of an input's feature-edge length the edges of a quad mesh follow
// (issue 32: a field-aligned layout should run its quads' edges along the creases).
#pragma once

#include <array>
#include <vector>

#include "core/poly_mesh.hpp"

namespace isoquad {

// A feature point counts as covered within this fraction of the quads' mean edge length from
// one of their edges (QualityReport::feature_coverage).
inline constexpr double kFeatureCoverageTolerance = 0.1;

// The feature edges of a triangle or polygon mesh as remeshing sees them: preparation's
// (prepare(): welded, triangulated, oriented, split into components) edges whose dihedral angle
// exceeds `feature_angle_deg` (prep::mark_features; boundary edges are not features), in the
// mesh's own coordinates. What preparation rejects or drops (a non-manifold edge without
// --repair, a component of fewer than 10 faces) has none.
std::vector<std::array<Vec3, 2>> feature_edges(const PolyMesh& mesh, double feature_angle_deg);

struct FeatureCoverage {
  double length = 0;   // of the feature edges
  double covered = 0;  // the part of `length` within the tolerance of an edge of the quads
  double share() const { return length > 0 ? covered / length : 1.0; }
};

// Each feature edge cut into equal pieces no longer than a quarter of `tolerance` (longer if
// the pieces would exceed a million), a piece covered when its midpoint is within `tolerance` of
// one of `edges` (a quad mesh's, each once; none: nothing is covered).
FeatureCoverage feature_coverage(const std::vector<std::array<Vec3, 2>>& features,
                                 const std::vector<std::array<Vec3, 2>>& edges, double tolerance);

}  // namespace isoquad
