// Validation and preparation of an input polygon soup (DESIGN.md §1): weld, triangulate, drop
// degenerate and duplicate faces, detect (and with `repair`, detach) non-manifold edges, split
// non-manifold vertices, orient consistently, split into components, normalize, mark features.
// What it cannot fix it rejects with an Error that names the input elements.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/element_data.hpp"
#include "core/poly_mesh.hpp"
#include "core/tri_mesh.hpp"

namespace isoquad {

struct PrepOptions {
  bool repair = false;              // detach non-manifold edges instead of rejecting (E101)
  bool weld_all = false;            // weld every coincident vertex (set for STL soups)
  double weld_epsilon = 0.0;        // weld distance relative to the bounding-box diagonal
  double feature_angle_deg = 60.0;  // dihedral angle above which an edge is a feature; <= 0: none
  bool diagnose = false;            // record would-be errors in the report instead of throwing
  // Delaunay flips inside flat regions (prep::flip_flat_edges), for quads that do not follow
  // the input's needle triangles.
  bool flip_flat = true;
};

// Maps input coordinates to a box centred at the origin with unit diagonal, and back.
struct Normalization {
  Vec3 center;
  double scale = 1.0;  // normalized = (p - center) * scale
  Vec3 apply(Vec3 p) const { return (p - center) * scale; }
  Vec3 invert(Vec3 p) const { return p / scale + center; }
};

// One thing preparation found: an error remesh raises (only collected when diagnosing), a
// repair it applied, or a warning.
struct InputIssue {
  enum class Severity { error, repaired, warning };
  Severity severity = Severity::warning;
  std::string code;     // E1xx for errors, W1xx for repairs and warnings
  std::string message;  // names input elements (0-based ids)
  uint32_t count = 0;   // how many elements it concerns
};

struct ComponentReport {
  uint32_t vertices = 0, edges = 0, faces = 0, boundary_loops = 0;
  int64_t euler = 0;
  int64_t genus = 0;  // orientable genus; for a non-orientable component, its non-orientable genus
  bool orientable = true;
  bool kept = true;  // false: rejected (non-orientable)
  double area = 0;   // in input units
  uint32_t feature_edges = 0;
  double min_angle_deg = 0;      // of the input's triangles, before the flips below
  uint32_t zero_area_faces = 0;  // left after the repair below (prep/steps.hpp kZeroArea)
  // That repair: needle edges collapsed, cap edges flipped, caps on the boundary removed.
  uint32_t zero_area_collapsed = 0, zero_area_flipped = 0, zero_area_dropped = 0;
  uint32_t flat_flips = 0;  // edges flipped inside flat regions (PrepOptions::flip_flat)
};

struct InputReport {
  uint32_t input_vertices = 0, input_faces = 0,
           input_polygons = 0;  // polygons: faces with > 3 sides
  uint32_t welded_vertices = 0, unused_vertices = 0;
  uint32_t degenerate_faces = 0;  // fewer than 3 distinct vertices (after welding), dropped
  uint32_t duplicate_faces = 0;   // same vertex set as an earlier face, dropped
  uint32_t non_manifold_edges = 0, split_vertices = 0, flipped_faces = 0;
  uint32_t removed_faces = 0;  // faces removed by --repair to make edges manifold
  bool orientable = true;
  Box3 bounding_box;  // input units
  std::vector<ComponentReport> components;
  std::vector<InputIssue> issues;
  bool has_errors() const;
};

struct PreparedComponent {
  TriMesh mesh;                       // normalized coordinates; outward for closed components
  VertexData<uint32_t> input_vertex;  // the input vertex each vertex came from
  FaceData<uint32_t> input_face;      // the input face (polygon) each triangle came from, or
                                      // one it overlaps, after flat flips
  EdgeData<char> feature;             // 1 where the dihedral angle exceeds the feature angle
  uint32_t report_index = 0;          // index into InputReport::components
};

struct PreparedMesh {
  std::vector<PreparedComponent> components;  // the kept ones
  Normalization normalization;
  InputReport report;
};

// \pre `soup` indices are in range (the readers guarantee it). Coordinates may be of any finite
// magnitude (1e-300 to 1e300 give the same normalized mesh).
// \throw Error(invalid_input) E013 a NaN or infinite coordinate, E101 non-manifold edge (without
//        repair), E103 nothing left, or a component without area for its size (collinear
//        faces, or a vertex so far from the rest that the rest shrinks to a point);
//        Error(unsupported_topology) E102 non-orientable. With options.diagnose these are
//        recorded in report.issues instead, and only the acceptable components are returned.
PreparedMesh prepare(const PolyMesh& soup, const PrepOptions& options = {});

}  // namespace isoquad
