// The local guard of the passes that move single quad corners over the surface after extraction
// (tip snapping, smoothing): a move of corner v is taken only if no quad around v gets a scaled
// Jacobian below min(its value before, `min_sj`), against its own (Newell) normal or against
// the surface normal just inside each corner, and the quads stay as close to the surface as
// they were (or within `tolerance`), both ways: every surface vertex closest to a quad the move
// changes, and sample points of those quads (for a move not made to bring them closer: within
// `tolerance`, whatever they were before). It keeps, per surface vertex, its closest quad and
// the distance, updated as moves are taken.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "extract/extract.hpp"
#include "metrics/aabb_tree.hpp"

namespace isoquad {

class SurfaceGuard {
 public:
  // `surface`: a tree of base's faces in order (face_triangles); the quads' SurfacePoints are
  // on `base`. `tolerance` (mesh units): what a move may leave any distance at.
  SurfaceGuard(QuadMesh& quads, const TriMesh& base, const AabbTree& surface, double tolerance,
               double min_sj);

  // v's quads' scaled Jacobians before a move: against their own normals and against the
  // corners' face normals (`rough`).
  struct Shape {
    std::vector<double> own, rough;
  };
  Shape shape(uint32_t v) const;

  // What moving v changes: its quads (`changed`: sample points checked) and the distances of
  // the surface vertices closest to one of them, which the move may take farther (`verts`, with
  // the tip being worked on: other vertices can only come closer). `others` is each such
  // vertex's distance to the quads next to the changed ones, which do not move.
  struct Local {
    std::vector<uint32_t> changed, verts;
    std::vector<uint32_t> near;  // per entry of verts: its closest quad of those measured
    std::vector<double> dist, others;
    std::vector<uint32_t> others_near;
    double samples = 0;  // largest distance of the samples on the changed quads to the surface
    double worst() const;
  };

  // Moves corner v to s if the guard allows it; with `improve`, only if the largest distance of
  // v's neighbourhood (to `tip` too, if not kInvalid) also drops. True if it moved. `shape` is
  // shape(v); `before` is v's neighbourhood as it is, measured on first use.
  bool try_move(uint32_t v, uint32_t tip, const SurfacePoint& s, Shape& shape,
                std::optional<Local>& before, bool improve);

  const std::vector<uint32_t>& quads_at(uint32_t v) const { return around_[v]; }
  uint32_t closest_quad(uint32_t surface_vertex) const { return closest_[surface_vertex]; }
  double distance(uint32_t surface_vertex) const { return distance_[surface_vertex]; }

 private:
  double quad_distance(uint32_t f, const Vec3& x) const;
  void closer(uint32_t f, const std::vector<uint32_t>& verts, std::vector<double>& dist,
              std::vector<uint32_t>& near) const;
  double surface_sj(uint32_t f, bool rough = false) const;
  double own_sj(uint32_t f) const;
  // The largest distance to the surface of quad f's sample points; with `limit`, it may stop
  // at the first beyond it.
  double quad_samples(uint32_t f, double limit = INFINITY) const;
  Local local(uint32_t v, uint32_t tip) const;
  void measure_vertices(Local& l) const;

  QuadMesh& qm_;
  const TriMesh& base_;
  const AabbTree& surface_;
  double tolerance_ = 0, min_sj_ = 0;
  std::vector<std::vector<uint32_t>> around_;  // quads at each corner
  // Per surface vertex: the quad it is closest to (among the quads near it) and the distance.
  std::vector<uint32_t> closest_;
  std::vector<double> distance_;
  std::vector<std::vector<uint32_t>> assigned_;  // per quad: the surface vertices closest to it
  // Per quad, as it is: surface_sj and quad_samples, NaN until measured.
  std::vector<double> exact_sj_, samples_;
  std::vector<double> sj_after_, samples_after_;  // try_move's, for the quads around v
};

}  // namespace isoquad
