#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <thread>

#include "core/predicates.hpp"
#include "core/refined_mesh.hpp"
#include "layout/layout.hpp"
#include "param/ordering.hpp"
#include "param/param.hpp"
#include "param/seam_system.hpp"
#include "param_checks.hpp"
#include "prep/prepare.hpp"
#include "seg/segment.hpp"
#include "shapes.hpp"

using namespace isoquad;

namespace {

struct Mapped {
  PreparedComponent component;
  SegmentResult seg;
  Layout layout;
  Param param;
  ParamReport report;
  const TriMesh& mesh() const { return seg.refined.mesh; }
};

// Segments into k patches, lays out (at `per_width` quads across the x extent, or at about
// `quads` quads) and parametrizes.
Mapped map_mesh(const PolyMesh& m, uint32_t k, double quads, const ParamOptions& po,
                int per_width = 0) {
  PreparedMesh p = prepare(m);
  Mapped r{std::move(p.components.at(0)), {}, {}, {}, {}};
  const Box3 box = r.component.mesh.bounding_box();
  const double h = per_width > 0 ? (box.hi.x - box.lo.x) / per_width : 0.0;
  SegmentOptions so;
  so.vsa.patches = k;
  r.seg = segment(r.component.mesh, r.component.feature, so);
  LayoutOptions lo;
  lo.quads = quads;
  lo.edge_length = h;
  LayoutReport lr;
  r.layout = solve_layout(r.mesh(), r.seg.labels, r.seg.feature, r.seg.meta, lo, lr);
  r.param = parametrize(r.mesh(), r.seg.labels, r.seg.meta, r.layout, po, r.report);
  return r;
}

ParamOptions relax(RelaxMode mode, WeightKind w = WeightKind::smvc) {
  ParamOptions o;
  o.relax = mode;
  o.weights = w;
  return o;
}

}  // namespace

TEST(Orient2d, ExactOnNearlyCollinearPoints) {
  // Points on the line y = x, perturbed by one unit in the last place: the naive determinant
  // rounds to the wrong sign or to zero for some of them; the exact one never does.
  const double base = 0.5 + 1e-16;
  int naive_wrong = 0;
  for (int i = 1; i < 64; ++i) {
    const double x = base * i / 7;
    const UV a{x, x}, b{2 * x, 2 * x}, c{3 * x, std::nextafter(3 * x, INFINITY)};
    EXPECT_GT(orient2d(a, b, c), 0) << i;
    const UV d{3 * x, std::nextafter(3 * x, -INFINITY)};
    EXPECT_LT(orient2d(a, b, d), 0) << i;
    EXPECT_EQ(orient2d(a, b, {3 * x, 3 * x}), 0) << i;
    const double naive = (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0]);
    naive_wrong += !(naive > 0);
  }
  EXPECT_GT(naive_wrong, 0) << "the case must defeat plain floating point";
  EXPECT_GT(orient2d({0, 0}, {1, 0}, {0, 1}), 0);
  EXPECT_LT(orient2d({0, 0}, {0, 1}, {1, 0}), 0);
}

TEST(Param, LinearPrecisionOfMeanValueWeights) {
  // A planar plate with jittered interior vertices, one patch, straight boundary sides placed
  // at chord length (an affine image of the plate): Floater's weights reproduce linear
  // functions, so every vertex lands on the affine image.
  PolyMesh m = test::grid_plate(24, 24);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.3 / 24, 0.3 / 24);
  for (Vec3& p : m.positions)
    if (p.x > 1e-9 && p.x < 1 - 1e-9 && p.y > 1e-9 && p.y < 1 - 1e-9) {
      p.x += jitter(rng);
      p.y += jitter(rng);
    }
  const Mapped r = map_mesh(m, 1, 0, relax(RelaxMode::adaptive, WeightKind::mvc), 12);
  ASSERT_EQ(r.seg.num_patches, 1u);
  ASSERT_EQ(r.layout.charts[0].width, 12);
  test::expect_certified(r.mesh(), r.seg.labels, r.seg.meta, r.layout, r.param);
  // The affine map from three plate corners (meta-vertices) to their lattice points.
  const MetaMesh& mm = r.seg.meta;
  ASSERT_GE(mm.vertices.size(), 3u);
  std::array<Vec3, 3> p;
  std::array<UV, 3> q;
  uint32_t found = 0;
  for (uint32_t f = 0; f < r.mesh().num_faces() && found < 3; ++f)
    for (int c = 0; c < 3 && found < 3; ++c) {
      const uint32_t v = r.mesh().face(f)[c];
      const uint32_t mv = mm.vertex_meta_vertex[v];
      bool dup = false;
      for (uint32_t i = 0; i < found; ++i) dup |= p[i] == r.mesh().position(v);
      if (mv == kInvalid || dup) continue;
      p[found] = r.mesh().position(v);
      q[found++] = r.param.map.uv[f][c];
    }
  ASSERT_EQ(found, 3u);
  // Solve q = M (p.x, p.y) + o from the three pairs.
  const double x1 = p[1].x - p[0].x, y1 = p[1].y - p[0].y, x2 = p[2].x - p[0].x,
               y2 = p[2].y - p[0].y;
  const double det = x1 * y2 - x2 * y1;
  ASSERT_GT(std::fabs(det), 1e-6);
  double worst = 0;
  for (uint32_t f = 0; f < r.mesh().num_faces(); ++f)
    for (int c = 0; c < 3; ++c) {
      const Vec3 d = r.mesh().position(r.mesh().face(f)[c]) - p[0];
      const double s = (d.x * y2 - x2 * d.y) / det, t = (x1 * d.y - d.x * y1) / det;
      for (int k = 0; k < 2; ++k) {
        const double want = q[0][k] + s * (q[1][k] - q[0][k]) + t * (q[2][k] - q[0][k]);
        worst = std::max(worst, std::fabs(r.param.map.uv[f][c][k] - want));
      }
    }
  EXPECT_LT(worst, 1e-10);
}

TEST(Param, LockedMapIsCertifiedOnSyntheticShapes) {
  const std::pair<const char*, PolyMesh> shapes[] = {{"sphere", test::icosphere(3)},
                                                     {"torus", test::torus(40, 16)},
                                                     {"cylinder", test::open_cylinder(32, 12)},
                                                     {"plate_with_hole", test::plate_with_hole(24)},
                                                     {"cube", test::subdivided_cube(8)}};
  for (const auto& [name, mesh] : shapes) {
    SCOPED_TRACE(name);
    const Mapped r = map_mesh(mesh, 0, 300, relax(RelaxMode::locked));
    test::expect_certified(r.mesh(), r.seg.labels, r.seg.meta, r.layout, r.param);
    // Seam vertices exactly on the straight segment between their meta-vertices.
    const MetaMesh& mm = r.seg.meta;
    for (uint32_t e = 0; e < mm.edges.size(); ++e) {
      const MetaEdge& me = mm.edges[e];
      const Chart& ch = r.layout.charts[me.left];
      UV a{}, b{};
      for (uint32_t i = 0; i < mm.faces[me.left].cycle.size(); ++i) {
        const uint32_t mv = mm.faces[me.left].start_vertex(i, mm.edges);
        const UV pos{double(ch.item_position[i][0]), double(ch.item_position[i][1])};
        if (mv == me.mv0) a = pos;
        if (mv == me.mv1) b = pos;
      }
      for (std::size_t i = 1; i + 1 < me.vertices.size(); ++i) {
        const UV x = r.param.map.position[me.vertices[i]];
        const double cross = (b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0]);
        EXPECT_NEAR(cross, 0.0, 1e-12);
      }
    }
    EXPECT_EQ(r.report.locked_meta_edges, r.report.meta_edges);
  }
}

TEST(Param, CubeMapIsAScaledIsometryAtTheFirstSolve) {
  // Mean value weights reproduce the flat faces exactly (the symmetrized ones need not near
  // the split corner triangles).
  const Mapped r =
      map_mesh(test::subdivided_cube(6), 6, 0, relax(RelaxMode::adaptive, WeightKind::mvc), 5);
  ASSERT_EQ(r.seg.num_patches, 6u);
  test::expect_certified(r.mesh(), r.seg.labels, r.seg.meta, r.layout, r.param);
  EXPECT_EQ(r.report.iterations, 1u);
  EXPECT_EQ(r.report.symbolic, 2u);  // the locked scalar system and the coupled one, once each
  EXPECT_EQ(r.report.factorizations, 2u);  // the locked map, then the relaxed one
  const Chart& c = r.layout.charts[0];
  // Every uv edge is the 3D edge scaled by W / (cube edge length).
  const Box3 box = r.mesh().bounding_box();
  const double scale = double(c.width) / (box.hi.x - box.lo.x);
  double worst = 0;
  for (uint32_t f = 0; f < r.mesh().num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const UV& a = r.param.map.uv[f][k];
      const UV& b = r.param.map.uv[f][(k + 1) % 3];
      const double l3 = norm(r.mesh().position(r.mesh().face(f)[(k + 1) % 3]) -
                             r.mesh().position(r.mesh().face(f)[k]));
      worst = std::max(worst, std::fabs(std::hypot(b[0] - a[0], b[1] - a[1]) - scale * l3));
    }
  EXPECT_LT(worst, 1e-9);
}

TEST(Param, RelaxedSeamsOnASphereAreCertifiedAndConsistent) {
  for (const WeightKind w : {WeightKind::smvc, WeightKind::mvc}) {
    const Mapped r = map_mesh(test::icosphere(4), 12, 600, relax(RelaxMode::adaptive, w));
    test::expect_certified(r.mesh(), r.seg.labels, r.seg.meta, r.layout, r.param);
    EXPECT_EQ(r.report.symbolic, 2u);  // the locked scalar system and the coupled one, once each
    EXPECT_EQ(r.report.factorizations, r.report.iterations + 1);
    EXPECT_LT(r.report.max_residual, 1e-10);
    EXPECT_FALSE(r.report.fell_back_to_locked);
    EXPECT_LT(r.report.locked_meta_edges, r.report.meta_edges);  // some seams stay free
  }
}

TEST(Param, AdaptiveNeedsFewerFactorizationsThanBisection) {
  const Mapped ad = map_mesh(test::icosphere(4), 12, 600, relax(RelaxMode::adaptive));
  const Mapped bi = map_mesh(test::icosphere(4), 12, 600, relax(RelaxMode::bisection));
  test::expect_certified(ad.mesh(), ad.seg.labels, ad.seg.meta, ad.layout, ad.param);
  test::expect_certified(bi.mesh(), bi.seg.labels, bi.seg.meta, bi.layout, bi.param);
  ASSERT_GT(bi.report.flipped_unstiffened, 0u) << "the case must need stiffening";
  EXPECT_LE(2 * ad.report.factorizations, bi.report.factorizations);
}

TEST(Param, SameInputSameMap) {
  const Mapped a = map_mesh(test::torus(40, 16), 0, 300, relax(RelaxMode::adaptive));
  const Mapped b = map_mesh(test::torus(40, 16), 0, 300, relax(RelaxMode::adaptive));
  ASSERT_EQ(a.param.map.uv.size(), b.param.map.uv.size());
  EXPECT_TRUE(a.param.map.uv.values() == b.param.map.uv.values());
}

TEST(Certificate, AngleSumsCatchARingThatWrapsTwice) {
  // A fan of six positive triangles whose ring winds twice around the centre: no face is
  // flipped, yet the map is not injective; only the angle sum at the centre shows it.
  std::vector<Vec3> pos{{0, 0, 0}};
  std::vector<Tri> faces;
  for (int k = 0; k < 6; ++k) {
    const double a = 2 * std::numbers::pi * k / 6;
    pos.push_back({std::cos(a), std::sin(a), 0});
    faces.push_back({0, uint32_t(1 + k), uint32_t(1 + (k + 1) % 6)});
  }
  const TriMesh mesh(pos, faces);
  const FaceData<uint32_t> labels(mesh.num_faces(), 0);
  MetaMesh meta;
  meta.vertex_meta_vertex = VertexData<uint32_t>(mesh.num_vertices(), kInvalid);
  meta.vertex_meta_edge = VertexData<uint32_t>(mesh.num_vertices(), kInvalid);
  Layout layout;
  layout.charts.resize(1);
  layout.charts[0].width = layout.charts[0].height = 10;
  ParamMap map;
  map.uv = FaceData<std::array<UV, 3>>(mesh.num_faces());
  auto ring = [](int k) {
    const double a = 2 * 2 * std::numbers::pi * k / 6;  // twice around
    return UV{5 + 2 * std::cos(a), 5 + 2 * std::sin(a)};
  };
  for (int k = 0; k < 6; ++k) map.uv[k] = {UV{5, 5}, ring(k), ring(k + 1)};
  const Certificate c = certify(mesh, labels, meta, layout, map);
  EXPECT_EQ(c.flipped, 0u);
  EXPECT_EQ(c.degenerate, 0u);
  ASSERT_FALSE(c.bad_vertices.empty());
  EXPECT_EQ(c.bad_vertices.front(), 0u);
  EXPECT_FALSE(c.ok());
}

TEST(Param, LockedScalarSystemMatchesTheCoupledSystemLocked) {
  // The locked map is solved as a scalar system of its own; the coupled system with every
  // meta-edge locked is the same map.
  for (const WeightKind w : {WeightKind::smvc, WeightKind::mvc}) {
    SCOPED_TRACE(w == WeightKind::smvc ? "smvc" : "mvc");
    const Mapped r = map_mesh(test::torus(40, 16), 0, 300, relax(RelaxMode::locked, w));
    SeamSystem system(r.mesh(), r.seg.labels, r.seg.meta, r.layout, w);
    ParamReport a, b;
    const ParamMap scalar = system.solve_locked(a);
    const ParamMap coupled = system.solve(EdgeData<double>(r.mesh().num_edges(), 1.0),
                                          std::vector<char>(r.seg.meta.edges.size(), 1), b);
    EXPECT_EQ(a.factorizations, 1u);
    double worst = 0;
    for (uint32_t f = 0; f < r.mesh().num_faces(); ++f)
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 2; ++k)
          worst = std::max(worst, std::fabs(scalar.uv[f][c][k] - coupled.uv[f][c][k]));
    EXPECT_LT(worst, 1e-9);
    EXPECT_TRUE(certify(r.mesh(), r.seg.labels, r.seg.meta, r.layout, scalar).ok());
  }
}

TEST(Ordering, NestedDissectionRanksArePermutationsExtendedAfterNeighbours) {
  const PreparedMesh p = prepare(test::icosphere(5));
  const TriMesh& mesh = p.components.at(0).mesh;
  const std::vector<uint32_t> ranks = nested_dissection_ranks(mesh);
  auto is_permutation = [](std::vector<uint32_t> r) {
    std::sort(r.begin(), r.end());
    for (uint32_t i = 0; i < r.size(); ++i)
      if (r[i] != i) return false;
    return true;
  };
  ASSERT_EQ(ranks.size(), mesh.num_vertices());
  EXPECT_TRUE(is_permutation(ranks));
  EXPECT_EQ(ranks, nested_dissection_ranks(mesh));  // deterministic
  // Split every third edge: each new vertex comes right after its highest-ranked old neighbour.
  std::vector<uint32_t> edges;
  for (uint32_t e = 0; e < mesh.num_edges(); e += 3) edges.push_back(e);
  const RefinedMesh refined = split_edges(identity_refinement(mesh), edges, nullptr, nullptr);
  const std::vector<uint32_t> extended = extend_ranks(refined.mesh, ranks);
  ASSERT_EQ(extended.size(), refined.mesh.num_vertices());
  EXPECT_TRUE(is_permutation(extended));
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v)  // the old vertices keep their order
    for (uint32_t w = v + 1; w < std::min(mesh.num_vertices(), v + 50); ++w)
      EXPECT_EQ(ranks[v] < ranks[w], extended[v] < extended[w]);
  for (uint32_t v = mesh.num_vertices(); v < refined.mesh.num_vertices(); ++v)
    refined.mesh.for_each_outgoing(v, [&](uint32_t h) {
      const uint32_t w = refined.mesh.to(h);
      if (w < mesh.num_vertices()) {
        EXPECT_GT(extended[v], extended[w]);
      }
    });
}

TEST(Param, SupernodalFactorizationsAreCertifiedAndRepeatableSideBySide) {
  // A torus large enough (11,200 vertices) for the supernodal factorization, whose dense blocks
  // go to BLAS. Two maps of it at once, on two threads, as several components or pipelines
  // would (OpenBLAS's sequential build is not safe to call so; param/blas_runtime.hpp), and the
  // same map again alone: certified, and equal to the last bit.
  const Mapped r = map_mesh(test::torus(160, 70), 0, 600, relax(RelaxMode::adaptive));
  ASSERT_GE(r.report.unknowns, 10000u);
  test::expect_certified(r.mesh(), r.seg.labels, r.seg.meta, r.layout, r.param);
  std::array<Param, 2> twice;
  {
    std::vector<std::jthread> threads;
    for (Param& p : twice)
      threads.emplace_back([&] {
        ParamReport report;
        p = parametrize(r.mesh(), r.seg.labels, r.seg.meta, r.layout, relax(RelaxMode::adaptive),
                        report);
      });
  }
  for (const Param& p : twice) EXPECT_TRUE(p.map.uv.values() == r.param.map.uv.values());
}

TEST(Param, GivenEliminationOrderGivesTheSameMap) {
  // Unknowns numbered by a nested dissection of the vertex graph (the pipeline's order on large
  // meshes) solve the same system: the same map up to rounding, certified alike.
  const Mapped r = map_mesh(test::torus(60, 24), 0, 400, relax(RelaxMode::adaptive));
  const std::vector<uint32_t> ranks = nested_dissection_ranks(r.mesh());
  ParamReport report;
  const Param ordered = parametrize(r.mesh(), r.seg.labels, r.seg.meta, r.layout,
                                    relax(RelaxMode::adaptive), report, &ranks);
  test::expect_certified(r.mesh(), r.seg.labels, r.seg.meta, r.layout, ordered);
  EXPECT_EQ(report.factorizations, r.report.factorizations);
  double worst = 0;
  for (uint32_t f = 0; f < r.mesh().num_faces(); ++f)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 2; ++k)
        worst = std::max(worst, std::fabs(ordered.map.uv[f][c][k] - r.param.map.uv[f][c][k]));
  EXPECT_LT(worst, 1e-8);
}
