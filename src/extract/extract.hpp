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

#include "core/poly_mesh.hpp"
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
  uint32_t quads = 0;   // quads placed: the layout's, or more where they were cut finer
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

// The quads' connectivity before they are placed (extraction's first half): every patch's
// W x H lattice cells, glued through shared ids, and the points of cells cut finer since. Each
// point has a representative place in one patch's chart, where the map locates it.
struct LatticeQuads {
  // Chart coordinates are integers in units of 1/kScale of the lattice, so that refined points
  // (thirds of thirds, bilinear in their quad's corners) are exact: a quad may be cut finer
  // kMaxLevel times.
  static constexpr int64_t kScale = 531441;  // 9^6
  static constexpr uint8_t kMaxLevel = 6;
  struct Point {
    uint32_t patch = kInvalid;                            // the chart `at` is in
    std::array<int64_t, 2> at{0, 0};                      // in 1/kScale lattice units
    uint32_t edge = kInvalid;                             // the meta-edge it lies on, if any
    std::array<uint32_t, 2> patches{kInvalid, kInvalid};  // patches whose quads use it
  };
  uint32_t meta_vertices = 0;  // ids below are meta-vertices (their Point is unused)
  std::vector<Point> points;
  std::vector<std::array<uint32_t, 4>> quads;                    // CCW
  std::vector<std::array<std::array<int64_t, 2>, 4>> corner_at;  // per quad, in its patch's chart
  std::vector<uint32_t> quad_patch;
  std::vector<uint8_t> level;  // per quad: how often it was cut finer (0: a lattice cell)
  // Per patch: the meta-edge of each unit segment of its rectangle's border (side_segment).
  std::vector<std::vector<uint32_t>> side_edge;
  // Index of the unit segment u-v of a W x H rectangle's border (bottom, right, top, left, each
  // from its low end), or SIZE_MAX if it is not on the border.
  static std::size_t side_segment(int64_t W, int64_t H, Lattice u, Lattice v);
};

// The lattice cells of the layout. \throw Error(internal, E601) if a lattice point has no id.
LatticeQuads lattice_quads(const MetaMesh& meta, const Layout& layout);

// Local refinement (beyond the paper): every quad with a marked corner (`marks` per point id) is
// cut at thirds in its chart, all of it when all four corners are marked, else by a template
// that meets its unmarked neighbours: one marked corner, three quads; two adjacent, seven (marks
// are first closed so that no quad has three marked corners or two opposite ones). The mesh
// stays pure quad and conforming, with new irregular vertices (valence 3 and 5) where the
// refinement ends. Points keep their ids; new points follow. Placed by the map, the finer quads
// follow the surface with the method's own contour lines at a third of the spacing. Returns how
// many quads were cut. \throw Error(internal, E602) past kMaxLevel.
uint32_t refine_lattice_quads(LatticeQuads& quads, const Layout& layout, std::vector<char> marks);

// Extraction's second half: each point located in the certified map (in its patch's faces, else
// across the nearest seam through the transition, else in the locked map) and placed on the
// input surface by barycentric interpolation through the refinement's provenance.
// \pre param.certificate.ok() or param is the locked map; layout passed check_layout.
// \throw Error(internal, E601) when a point cannot be placed at all (a bug).
QuadMesh place_quads(const RefinedMesh& refined, const TriMesh& base,
                     const FaceData<uint32_t>& labels, const MetaMesh& meta, const Layout& layout,
                     const Param& param, const LatticeQuads& quads, ExtractReport& report);

// lattice_quads, then place_quads.
// \pre param.certificate.ok() or param is the locked map; layout passed check_layout.
// \throw Error(internal, E601) when a lattice point cannot be placed at all (a bug).
QuadMesh extract_quads(const RefinedMesh& refined, const TriMesh& base,
                       const FaceData<uint32_t>& labels, const MetaMesh& meta, const Layout& layout,
                       const Param& param, ExtractReport& report);

// The quads as a polygon mesh (for topology_of, metrics/quality.hpp); nothing else is kept.
PolyMesh as_poly(const QuadMesh& quads);

}  // namespace isoquad
