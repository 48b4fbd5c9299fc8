// Tangential smoothing, the last pass of a component: vertices stay on the surface, no quad
// folds, no distance grows.
#include <gtest/gtest.h>

#include "corpus.hpp"
#include "extract/snap.hpp"
#include "extract/surface_walk.hpp"
#include "io/read_mesh.hpp"
#include "metrics/aabb_tree.hpp"
#include "metrics/quality.hpp"
#include "pipeline/pipeline.hpp"
#include "prep/prepare.hpp"
#include "remesh_shape.hpp"
#include "shapes.hpp"

using namespace isoquad;
using namespace isoquad::test;

TEST(Smooth, KeepsVerticesOnTheSurfaceAndUnfolds) {
  const Remeshed r = remesh_shape(test::torus(48, 20), 0, 600);
  QuadMesh q = r.run.quads;
  const TriMesh& base = r.prep.components[0].mesh;
  auto folded = [](const QuadMesh& m) {
    PolyMesh p;
    p.positions = m.positions;
    for (const auto& f : m.quads) p.add_face({f[0], f[1], f[2], f[3]});
    return measure_quality(p, nullptr);
  };
  const QualityReport before = folded(q);
  SmoothReport report;
  SmoothOptions so;
  so.iterations = 10;
  so.edge_length = r.run.layout.edge_length;
  smooth_quads(q, base, r.run.seg.meta, so, report);
  const QualityReport after = folded(q);
  EXPECT_EQ(report.iterations, 10u);
  EXPECT_GT(report.moves, 0u);
  EXPECT_LE(after.sj_nonpositive, before.sj_nonpositive);
  // What smoothing is for: the worst quad is no worse and the spacing is more even (the mean
  // scaled Jacobian may move either way: averaging positions is not an angle optimizer).
  EXPECT_GE(after.sj_min, before.sj_min);
  EXPECT_LT(after.edge_cv, before.edge_cv);
  // No crease and no boundary: the meta-vertices move too.
  uint32_t meta_moved = 0;
  for (std::size_t v = 0; v < q.positions.size(); ++v) {
    EXPECT_LT(norm(position_of(base, q.surface[v]) - q.positions[v]), 1e-12);
    meta_moved +=
        q.vertex_meta_vertex[v] != kInvalid && !(q.positions[v] == r.run.quads.positions[v]);
  }
  EXPECT_GT(meta_moved, 0u);
}

// With the surface's tree, smoothing judges every quad around a moved vertex by its corners'
// scaled Jacobians against the surface normal as well as against its own normal, quad by quad:
// no quad ends below min(its value before, 0.2) by either measure, so none folds against the
// surface, and the spacing still evens out. fandisk at the default size (6,750 quads, creases):
// guarded by the quads' own normals only, the same ten iterations fold quads against the
// surface.
TEST(Smooth, GuardedByTheSurfaceFoldsNoQuad) {
  const ReadResult in = read_mesh(test::data_dir() / "fandisk.off");
  const Remeshed r = remesh_shape(in.mesh, 0, 0);
  const TriMesh& base = r.prep.components[0].mesh;
  PolyMesh reference;
  reference.positions = base.positions();
  for (const Tri& t : base.faces()) reference.add_face({t[0], t[1], t[2]});
  auto quality = [&](const QuadMesh& m) {
    PolyMesh p;
    p.positions = m.positions;
    for (const auto& f : m.quads) p.add_face({f[0], f[1], f[2], f[3]});
    return measure_quality(p, &reference);
  };
  QuadMesh q = r.run.quads;
  const QualityReport before = quality(q);
  const AabbTree tree(face_triangles(base));
  SmoothReport report;
  SmoothOptions so;
  so.iterations = 10;
  so.edge_length = r.run.layout.edge_length;
  smooth_quads(q, base, r.run.seg.meta, so, report, &tree);
  const QualityReport after = quality(q);
  EXPECT_GT(report.moves, 0u);
  EXPECT_GT(report.rejected, 0u);
  EXPECT_LE(after.sj_surface_nonpositive, before.sj_surface_nonpositive);
  EXPECT_GE(after.sj_surface_min, std::min(before.sj_surface_min, 0.2) - 1e-9);
  EXPECT_GE(after.sj_min, std::min(before.sj_min, 0.2) - 1e-9);
  EXPECT_LT(after.edge_cv, before.edge_cv);
  // Vertices on creases, and the meta-vertices where they end, stay.
  const MetaMesh& meta = r.run.seg.meta;
  std::vector<char> on_crease(meta.vertices.size(), 0);
  for (const MetaEdge& e : meta.edges)
    if (e.feature) on_crease[e.mv0] = on_crease[e.mv1] = 1;
  uint32_t held = 0;
  for (std::size_t v = 0; v < q.positions.size(); ++v) {
    EXPECT_LT(norm(position_of(base, q.surface[v]) - q.positions[v]), 1e-12);
    const uint32_t m = q.vertex_meta_vertex[v], e = q.vertex_meta_edge[v];
    if ((m != kInvalid && on_crease[m]) ||
        (m == kInvalid && e != kInvalid && meta.edges[e].feature)) {
      EXPECT_EQ(q.positions[v], r.run.quads.positions[v]);
      ++held;
    }
  }
  EXPECT_GT(held, 100u);
}

// Smoothing after the tip snapping: the corners the snapping put onto the bumps stay there,
// and no move takes the quads farther from the surface than they were or 0.1 h, so the
// two-sided distance does not grow. Unguarded by distance (`far` infinite), the same sweeps pull
// the quads off the rim (4.3% -> 6.1% of the diagonal when this was written).
TEST(Smooth, ComesNoFartherFromTheSurfaceAndKeepsSnappedCorners) {
  // A flat ellipsoid (its rim's radius of curvature a third of a quad) with bumps.
  PolyMesh bumpy = test::icosphere(4);
  for (std::size_t v = 0; v < bumpy.positions.size(); v += 97)
    bumpy.positions[v] = 1.12 * bumpy.positions[v];
  for (Vec3& x : bumpy.positions) x[2] *= 0.25;
  const Remeshed r = remesh_shape(bumpy, 0, 300);
  const std::vector<uint32_t>& snapped = r.run.snap_report.moved;
  ASSERT_GT(snapped.size(), 0u);
  const TriMesh& base = r.prep.components[0].mesh;
  const PolyMesh reference = component_as_poly(base);
  auto smoothed = [&](double far, const std::vector<uint32_t>& pinned, SmoothReport& report) {
    QuadMesh q = r.run.quads;
    SmoothOptions so;
    so.iterations = 10;
    so.edge_length = r.run.layout.edge_length;
    so.far = far;
    smooth_quads(q, base, r.run.seg.meta, so, report, nullptr, pinned);
    return q;
  };
  SmoothReport pinned, guarded, loose;
  const QuadMesh q = smoothed(0.1, snapped, pinned);
  const QuadMesh unpinned = smoothed(0.1, {}, guarded);
  const QuadMesh unguarded = smoothed(INFINITY, {}, loose);
  EXPECT_GT(pinned.moves, 0u);
  EXPECT_GT(guarded.rejected, loose.rejected);
  for (const uint32_t v : snapped) EXPECT_EQ(q.positions[v], r.run.quads.positions[v]);
  const QualityReport before = measure_quality(as_poly(r.run.quads), &reference);
  Box3 box;
  for (const Vec3& x : reference.positions) box.add(x);
  const double bound =
      std::max(before.hausdorff, 0.1 * r.run.layout.edge_length / norm(box.hi - box.lo));
  for (const QuadMesh* m : {&q, &unpinned}) {
    const QualityReport after = measure_quality(as_poly(*m), &reference);
    EXPECT_LE(after.hausdorff, 1.01 * bound);
    EXPECT_EQ(after.sj_nonpositive, 0u);
    EXPECT_LT(after.edge_cv, before.edge_cv);
  }
  EXPECT_GT(measure_quality(as_poly(unguarded), &reference).hausdorff, 1.2 * before.hausdorff);
}

// In the pipeline, smoothing is the component's last pass: the same quads as without it, the
// corners the tip snapping moved where it put them, the others moved by it on the component's
// surface, and the mesh more even.
TEST(Smooth, IsTheLastPassOfAComponent) {
  PolyMesh bumpy = test::icosphere(4);
  for (std::size_t v = 0; v < bumpy.positions.size(); v += 97)
    bumpy.positions[v] = 1.12 * bumpy.positions[v];
  for (Vec3& x : bumpy.positions) x[2] *= 0.25;
  const PreparedMesh prep = prepare(bumpy);
  PipelineOptions o;
  o.quads = 300;
  EXPECT_EQ(o.smooth, 3u);  // the default
  o.smooth = 0;
  const ComponentRun plain = run_component(prep, 0, o);
  o.smooth = 3;
  const ComponentRun smoothed = run_component(prep, 0, o);
  EXPECT_EQ(plain.smooth_report.iterations, 0u);
  EXPECT_EQ(smoothed.smooth_report.iterations, 3u);
  EXPECT_GT(smoothed.smooth_report.moves, 0u);
  ASSERT_EQ(smoothed.quads.quads, plain.quads.quads);
  ASSERT_GT(plain.snap_report.moved.size(), 0u);
  EXPECT_EQ(smoothed.snap_report.moved, plain.snap_report.moved);
  for (const uint32_t v : plain.snap_report.moved)
    EXPECT_EQ(smoothed.quads.positions[v], plain.quads.positions[v]);
  const TriMesh& mesh = prep.components[0].mesh;
  uint32_t moved = 0;
  for (std::size_t v = 0; v < plain.quads.positions.size(); ++v) {
    EXPECT_LT(norm(position_of(mesh, smoothed.quads.surface[v]) - smoothed.quads.positions[v]),
              1e-12);
    moved += !(smoothed.quads.positions[v] == plain.quads.positions[v]);
  }
  EXPECT_GT(moved, plain.quads.positions.size() / 4);
  const PolyMesh reference = component_as_poly(mesh);
  const QualityReport before = measure_quality(as_poly(plain.quads), &reference);
  const QualityReport after = measure_quality(as_poly(smoothed.quads), &reference);
  EXPECT_EQ(after.sj_invalid, 0u);
  EXPECT_GT(after.sj_mean, before.sj_mean);
  EXPECT_LT(after.edge_cv, before.edge_cv);
}
