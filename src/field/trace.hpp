// Separatrices of a cross field, traced over the surface as a motorcycle graph (FIELD_LAYOUT.md
// §3; Eppstein et al. 2008, Myles et al. 2014): from every singular vertex and every node of the
// features and the boundary, each ray of the field starts a trace that runs along its direction
// family (matched across edges by the period jumps) until it reaches a feature, the boundary or
// another trace. All traces advance together by arc length, so where two meet, the later one
// stops (a T-junction) and the crossing graph is canonical.
#pragma once

#include <cstdint>
#include <vector>

#include "core/refined_mesh.hpp"
#include "field/cross_field.hpp"

namespace isoquad {

// A ray of the field at a node: the vertex, the face it leaves into and the field's arm there
// (Trace::source, first_face, first_arm of its trace).
struct RayId {
  uint32_t vertex = kInvalid, face = kInvalid;
  int arm = 0;
  bool operator==(const RayId&) const = default;
};

struct TraceOptions {
  double edge_length = 0;  // h (mesh units); a trace is capped at min(200 h, 4 sqrt(area))
  // A separatrix passing within capture * h of another node, coming in along one of that
  // node's rays (within 30 degrees, seen from the node), is taken to be that ray's separatrix too:
  // it ends at the node, and the node does not trace that ray (FIELD_LAYOUT.md §3 rule 3). 0: no
  // capture.
  double capture = 0.5;
  // A trace that runs beside a parallel track (another trace, itself further on, a feature or
  // the boundary) closer than strip * h along at least half of its length, or that finds no
  // end, is deleted and the graph traced again without it (§3 rule 4, §5), for up to `rounds`
  // rounds: it would bound a strip thinner than a quad.
  double strip = 0.5;
  // A trace that stops on a track, a feature or the boundary closer than gap * h to another
  // point of it (another trace's end, a node) is deleted the same way: the meta-edge between
  // them would be shorter than half a quad, which the integer lengths stretch to one, more than
  // twice its length (more quads than asked for), or cannot (a strip closing around a tube a
  // fraction of a quad off; layout/ slides a corner over such an edge).
  double gap = 0.5;
  uint32_t rounds = 6;
  // Regular interior vertices that emit the field's four rays as well (FIELD_LAYOUT.md §4): in
  // a patch no trace makes a disk (a handle, a tube), their traces close loops around it or
  // run from one seed to the other.
  std::vector<uint32_t> seeds;
  // Rays deleted from the start (the coarse layout's choice, field_segment.hpp), under the same
  // rule as the strip deletions: never two neighbouring rays of one node, never a connection.
  std::vector<RayId> removed;
};

enum class TraceEnd {
  boundary,  // on a boundary edge
  feature,   // on a feature edge the field is aligned to
  track,     // on another trace (or itself): a T-junction
  cap,       // longer than the cap: a limit cycle or a spiral
  sink,      // the field turns back at an edge, and so does the trace's own direction
  node,      // at another node it passed close to, along one of that node's rays (a connection)
};

struct Trace {
  uint32_t source = kInvalid;  // the vertex it starts from
  uint32_t first_face = kInvalid;
  int first_arm = 0;  // the field's arm 0..3 it starts along, in first_face
  // The polyline: the source vertex, one point per edge crossed, then the end point. points[i]
  // and points[i + 1] lie in faces[i].
  std::vector<SurfacePoint> points;
  // Per point, the edge it lies on and its fraction from the start of the edge's halfedge
  // (EdgePoint, refined_mesh.hpp); edge kInvalid for the source vertex, for an end inside a
  // face (on another trace) and for an end at a node (TraceEnd::node).
  std::vector<EdgePoint> on_edge;
  std::vector<uint32_t> faces;
  TraceEnd end = TraceEnd::cap;
  uint32_t end_trace = kInvalid;   // the trace it stopped on (TraceEnd::track)
  uint32_t end_vertex = kInvalid;  // the node it ends at (TraceEnd::node)
  double length = 0;               // on the field's surface
};

struct TraceResult {
  std::vector<Trace> traces;
  std::vector<uint32_t> nodes;  // vertices that emitted traces
  // Singular vertices whose rays found in their one-ring do not number 4 - 4I (a ray hidden in a
  // period jump, or counted twice along an edge).
  uint32_t ray_mismatches = 0;
  uint32_t truncated = 0;           // traces cut back where a later arrival had crossed them first
  uint32_t straight_crossings = 0;  // faces crossed straight on past a sink edge
  uint32_t head_on = 0;             // separatrices traced from both ends, joined where they met
  uint32_t connections = 0;         // separatrices joining two nodes, laid before the others
  uint32_t deleted = 0;             // rays not traced: their traces ran beside another track
  uint32_t rounds = 0;              // motorcycle graphs traced
  // Nodes with a deleted ray: there, two sectors are one, which turns by two quarters.
  std::vector<uint32_t> partial_nodes;
};

// The rays every node emits and their traces. Nodes: singular interior vertices (4 - 4I rays),
// and vertices on feature or boundary edges where the constraint curve ends, branches or turns
// by more than 45 degrees, or where the field is singular on the boundary (the rays strictly
// inside the sectors between the constraint edges).
TraceResult trace_separatrices(const CrossField& field, const TraceOptions& options);

// A surface point's position on a mesh of the field's connectivity (the input, or the field's
// smoothed surface).
Vec3 position_on(const TriMesh& mesh, const SurfacePoint& p);

}  // namespace isoquad
