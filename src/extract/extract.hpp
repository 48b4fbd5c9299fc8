// Quad extraction (paper §2 step 3, §4; DESIGN.md §8): connectivity from the layout, geometry
// from the map. Each patch's W x H lattice becomes a grid of quads, glued to its neighbours
// through shared ids for the lattice points on meta-edges and meta-vertices, so the result is
// pure quad, manifold and of the input's topology by construction. Each lattice point is then
// located in the certified map (in its patch's faces, else across the nearest seam through the
// transition, else in the locked map) and placed on the input surface by barycentric
// interpolation through the refinement's provenance.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "core/refined_mesh.hpp"
#include "layout/layout.hpp"
#include "param/param.hpp"

namespace isoquad {

struct QuadMesh {
  std::vector<Vec3> positions;                 // on the base mesh (the prepared component)
  std::vector<SurfacePoint> surface;           // per vertex: base face and barycentrics
  std::vector<std::array<uint32_t, 4>> quads;  // CCW seen from outside
  std::vector<uint32_t> quad_patch;
  std::vector<uint32_t> vertex_meta_vertex;  // per vertex: meta-vertex or kInvalid
  std::vector<uint32_t> vertex_meta_edge;    // per vertex: meta-edge it lies on, or kInvalid
  enum class Placed : uint8_t { meta, direct, across, locked };
  std::vector<Placed> placed;  // how each vertex was located
  // Where the first untangling found each vertex; later rounds keep their bounds from there.
  std::vector<Vec3> mapped;
  // Per vertex: a diagonal collapse merged another corner into it (extract/collapse.hpp). The
  // untangler holds it to covering its point like a singularity.
  std::vector<char> merged;
};

// The smallest over quad f's corners of n . (e1 x e2) / (|e1| |e2|), with e1 and e2 the corner's
// edges and n = normal(v, x): v the corner's vertex, x a point just inside the corner (0.05 of
// the way along both edges, where `isoquad quality` takes the surface normal: at a vertex on a
// crease, the side the quad lies on). -1 if a corner has an edge of length 0.
template <class Normal>
double quad_corner_sj(const QuadMesh& qm, uint32_t f, Normal&& normal) {
  const auto& q = qm.quads[f];
  double sj = 1;
  for (int k = 0; k < 4; ++k) {
    const Vec3& p = qm.positions[q[k]];
    const Vec3 e1 = qm.positions[q[(k + 1) % 4]] - p, e2 = qm.positions[q[(k + 3) % 4]] - p;
    const double l = norm(e1) * norm(e2);
    if (!(l > 0)) return -1;
    sj = std::min(sj, dot(normal(q[k], p + 0.05 * (e1 + e2)), cross(e1, e2)) / l);
  }
  return sj;
}

struct ExtractReport {
  uint32_t direct = 0;  // lattice points found in their own patch's faces
  uint32_t across = 0;  // found across a seam, through its transition
  uint32_t locked = 0;  // placed with the locked map (fallback)
  uint32_t meta = 0;    // meta-vertices (exact)
  // The verifier (DESIGN.md §8.4): lattice points the relaxed map covers more than once (0 for
  // a bijective map), and patches that therefore took the locked map's geometry.
  uint32_t multiply_covered = 0;
  uint32_t patches_locked = 0;
  double seconds = 0;
};

// Distance from x to the quad with these corners, taken as four triangles about its centroid.
double distance_to_quad(const std::array<Vec3, 4>& corners, const Vec3& x);
// The same for quad q of `positions`.
double distance_to_quad(const std::vector<Vec3>& positions, const std::array<uint32_t, 4>& q,
                        const Vec3& x);

// The quads as `isoquad quality` measures them: each split along the diagonal from its first
// corner (two triangles, 2f and 2f + 1).
std::vector<std::array<Vec3, 3>> fan_triangles(const QuadMesh& quads);

// The surface's triangles in face order (triangle f is face f), for an AabbTree.
std::vector<std::array<Vec3, 3>> face_triangles(const TriMesh& surface);

// \pre param.certificate.ok() or param is the locked map; layout passed check_layout.
// \throw Error(internal, E601) when a lattice point cannot be placed at all (a bug).
QuadMesh extract_quads(const RefinedMesh& refined, const TriMesh& base,
                       const FaceData<uint32_t>& labels, const MetaMesh& meta, const Layout& layout,
                       const Param& param, ExtractReport& report);

}  // namespace isoquad
