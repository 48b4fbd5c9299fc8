// Quality of a quad mesh (DESIGN.md §9.1): validity (pure quad, manifold, topology against the
// input), singularities, element shape (scaled Jacobian, angles, edge lengths, aspect ratio, area
// spread), distance to the input surface (two-sided, area-sampled, over the input's
// bounding-box diagonal) and how much of the input's feature edges the quads' edges follow.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/poly_mesh.hpp"
#include "metrics/aabb_tree.hpp"

namespace isoquad {

struct Topology {
  int64_t euler = 0;
  uint32_t components = 0, boundary_loops = 0;
  int64_t genus() const;  // summed over components: (2 c - chi - b) / 2
};

// A quad is valid only if its scaled Jacobian against its own (Newell) normal is above this: at
// or below it the quad is folded, or has a corner of 180 degrees or an edge of length 0.
inline constexpr double kMinValidScaledJacobian = 1e-3;

struct QualityReport {
  uint64_t vertices = 0, faces = 0, non_quads = 0;
  bool pure_quad = false, edge_manifold = false, vertex_manifold = false, oriented = false;
  Topology topology;
  std::optional<Topology> reference_topology;
  bool same_topology = false;       // as the reference (when there is one)
  std::map<int, uint32_t> valence;  // interior vertices by number of quads
  uint32_t irregular = 0;           // interior vertices with valence != 4
  // Scaled Jacobian per quad: the minimum over its four corners of n . (e1 x e2)/(|e1||e2|), n
  // the quad's own (Newell) normal.
  double sj_min = 0, sj_mean = 0, sj_below_half = 0;  // the last in percent
  uint32_t sj_invalid = 0;                            // at most kMinValidScaledJacobian
  uint32_t sj_nonpositive = 0;                        // at most 0 (of them)
  // The same against the input surface's normal at each corner (closest input face).
  double sj_surface_min = 0;
  uint32_t sj_surface_nonpositive = 0;
  double angle_deviation_mean = 0, angle_deviation_max = 0;  // |corner angle - 90| in degrees
  double edge_mean = 0, edge_cv = 0;
  // Over the 4-sided faces. Aspect ratio per quad: the mean lengths of its two pairs of opposite
  // sides, the larger over the smaller (infinite where the smaller is 0); its mean, 95th
  // percentile (nearest rank) and the percentage of quads above 2. Area: the vector area (half
  // the Newell vector); its standard deviation over its mean.
  double aspect_mean = 0, aspect_p95 = 0, aspect_above_2 = 0;
  double area_cv = 0;
  double hausdorff = 0, mean_distance = 0;  // over the reference's bounding-box diagonal
  // Where the Hausdorff distance is reached: a point of the input farthest from the quads
  // (hausdorff_on_input), else a point of the quads farthest from the input.
  Vec3 hausdorff_at;
  bool hausdorff_on_input = false;
  // The reference's feature edges (feature_edges(), at feature_angle_deg): their total length and
  // the share of it within kFeatureCoverageTolerance times edge_mean of an edge of the quads
  // (feature_coverage(); 1 when there is no feature edge).
  double feature_angle_deg = 0, feature_length = 0, feature_coverage = 1;
  bool has_reference = false;
};

// The two-sided distance's maximum (the Hausdorff distance) is found to within this fraction of
// itself: every point of both surfaces is that close to a point measured.
inline constexpr double kMaxDistanceRelativeError = 1e-3;

struct QualityOptions {
  uint32_t samples = 20000;  // area samples per surface for the distances
  uint64_t seed = 1;
  double feature_angle_deg = 60;  // the reference's feature edges (as PrepOptions'; 0: none)
};

// Euler characteristic, components and boundary loops; optionally whether every edge has one or
// two faces, every vertex one fan of corners, the faces a consistent orientation, which vertices
// are on the boundary and how many corners each vertex has.
Topology topology_of(const PolyMesh& m, bool* edge_manifold, bool* vertex_manifold, bool* oriented,
                     std::vector<uint32_t>* boundary_vertex_flag,
                     std::vector<uint32_t>* corner_count);

// What differs from `input`'s topology in `output`'s, in words, each as "before -> after":
// "genus 2 -> 1, boundary loops 0 -> 1, connected pieces 1 -> 2" (the Euler characteristic where
// none of those differs but it does); empty when the two are the same.
std::string topology_change(const Topology& input, const Topology& output);

// \pre quads has at least one face. `reference` (triangles or polygons) enables topology
// comparison, surface-normal Jacobians and distances.
QualityReport measure_quality(const PolyMesh& quads, const PolyMesh* reference,
                              const QualityOptions& options = {});

// The scaled Jacobian of the quad (q0, q1, q2, q3) against its Newell normal, as
// QualityReport's per-quad value: the minimum over its corners of n . (e1 x e2)/(|e1||e2|), 0 at
// a corner with an edge of length 0.
double quad_scaled_jacobian(const std::array<Vec3, 4>& q);

// The same per corner: corner i's n . (e1 x e2)/(|e1||e2|), 0 where an edge has length 0 (their
// minimum is quad_scaled_jacobian).
std::array<double, 4> quad_corner_scaled_jacobians(const std::array<Vec3, 4>& q);

// The aspect ratio of the quad (q0, q1, q2, q3), as QualityReport's: max(a, b) / min(a, b), a
// the mean length of sides q0q1 and q2q3, b of q1q2 and q3q0; infinite where min(a, b) is 0.
double quad_aspect_ratio(const std::array<Vec3, 4>& q);

// Two-sided distance between a triangle set and the triangles of an AabbTree (as
// QualityReport's, before the division by the diagonal): the maximum to within
// kMaxDistanceRelativeError (a branch and bound over each set's triangles), the mean over
// `samples` area samples (each triangle's drawn from `seed` and its corners) and every vertex of
// each set to the other set.
struct SurfaceDistance {
  double max = 0, mean = 0;  // the larger one-sided maximum; the mean of the one-sided means
  Vec3 at;                   // where the maximum is reached
  bool on_b = false;         // `at` is on b (a point of b farthest from a), else on a
};
// \pre both sets have a triangle.
SurfaceDistance surface_distance(const std::vector<std::array<Vec3, 3>>& a, const AabbTree& b,
                                 uint32_t samples, uint64_t seed);

// Per face, the scaled Jacobian against the reference's normal at each corner (as
// QualityReport::sj_surface_min): <= 0 marks a folded face.
std::vector<double> surface_scaled_jacobians(const PolyMesh& quads, const PolyMesh& reference);

}  // namespace isoquad
