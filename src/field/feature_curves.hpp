// Feature curves: the feature edges chained into curves between nodes (a vertex where the count
// of feature edges is not two, or where the chain turns by more than a corner angle). The cross
// field is hard-aligned only to feature networks long enough to carry quad edges: on an organic
// mesh a 60-degree dihedral threshold marks scattered short creases (noise, a horn tip), and
// each of them, as a hard constraint, pins the field in its own direction and breeds
// singularities.
#pragma once

#include <cstdint>
#include <vector>

#include "core/element_data.hpp"
#include "core/tri_mesh.hpp"

namespace isoquad {

struct FeatureCurve {
  std::vector<uint32_t> halfedges;  // consecutive, head to tail
  double length = 0;
  bool closed = false;
};

// The feature edges as curves, each edge in exactly one curve; a curve breaks at a vertex whose
// feature-edge count is not 2 or where it turns by more than `corner_deg`.
std::vector<FeatureCurve> feature_curves(const TriMesh& mesh, const EdgeData<char>& feature,
                                         double corner_deg = 45);

// Which feature networks (edges connected through shared vertices) constrain the field, by
// their total length and their length-weighted mean dihedral angle (mesh units, degrees).
struct FeatureNetworkRule {
  double min_length = 0;  // shorter networks are dropped
  // Networks shorter than weak_length whose mean dihedral angle is below weak_angle_deg are
  // dropped too: a CAD model's creases are sharp (90 degrees and more) or form long networks;
  // an organic mesh's scattered creases barely pass the feature angle and are short.
  double weak_length = 0, weak_angle_deg = 0;
};

// The feature edges of the networks `rule` keeps.
EdgeData<char> long_features(const TriMesh& mesh, const EdgeData<char>& feature,
                             const FeatureNetworkRule& rule, uint32_t* dropped_networks = nullptr);

}  // namespace isoquad
