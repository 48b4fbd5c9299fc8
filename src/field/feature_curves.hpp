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

// The feature edges of the networks (edges connected through shared vertices) at least
// `min_length` long in all (mesh units): a CAD model's creases form long networks even where one
// crease is short, while noise on an organic mesh marks small isolated ones.
EdgeData<char> long_features(const TriMesh& mesh, const EdgeData<char>& feature, double min_length,
                             uint32_t* dropped_networks = nullptr);

}  // namespace isoquad
