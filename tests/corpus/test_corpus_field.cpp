// The cross field on every corpus mesh at the size of 1,500 quads: Poincare-Hopf holds (the
// solver checks it and throws otherwise), every face with a feature or boundary edge follows it,
// no singularity away from the features is beyond +-1/2, the same input gives the same field, and
// the corpus's singular vertices stay within a regression bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "corpus.hpp"
#include "field/cross_field.hpp"
#include "field/field_segment.hpp"
#include "field/trace.hpp"
#include "io/read_mesh.hpp"
#include "layout/layout.hpp"
#include "metrics/quality.hpp"
#include "pipeline/remesh.hpp"
#include "pipeline/sizing.hpp"
#include "prep/prepare.hpp"
#include "seg/patch_topology.hpp"

using namespace isoquad;

namespace {

class CorpusField : public testing::TestWithParam<const char*> {};

// The cross field of a corpus mesh's first component at the size of 1,500 quads.
struct Field {
  RefinedMesh refined;
  EdgeData<char> feature;
  CrossField cf;
};

Field field_of(const PreparedMesh& p) {
  const PreparedComponent& c = p.components.at(0);
  Field out;
  out.feature = c.feature;
  out.refined = split_constraint_conflicts(identity_refinement(c.mesh), out.feature);
  CrossFieldOptions o;
  o.edge_length = edge_length_for_quads(out.refined.mesh, 1500);
  out.cf = compute_cross_field(out.refined.mesh, out.feature, o);
  return out;
}

}  // namespace

TEST_P(CorpusField, AlignedToFeaturesWithQuarterSingularities) {
  ISOQUAD_CORPUS_MESH(path, GetParam());
  const PreparedMesh p = prepare(read_mesh(path).mesh);
  const Field field = field_of(p);
  const CrossField& cf = field.cf;
  const TriMesh& m = field.refined.mesh;
  ASSERT_EQ(cf.angle.size(), m.num_faces());
  // Away from the constrained faces, no singularity is more than +-1/2 beyond the
  // angle defect there in quarter turns (a spike's tip with a defect near 2 pi asks for +1; at a
  // crease's corner or tip, the crease dictates the turning, whatever it is).
  VertexData<char> on_feature(m.num_vertices(), 0);
  for (uint32_t f = 0; f < m.num_faces(); ++f)
    if (cf.constrained[f])
      for (uint32_t v : m.face(f)) on_feature[v] = 1;
  int64_t sum = 0;
  for (uint32_t v = 0; v < m.num_vertices(); ++v) {
    sum += cf.index4[v];
    if (on_feature[v]) continue;
    double defect = 2 * std::numbers::pi;
    cf.surface.for_each_outgoing(v, [&](uint32_t h) { defect -= corner_angle(cf.surface, h); });
    EXPECT_LE(std::abs(cf.index4[v] - std::lround(defect / (std::numbers::pi / 2))), 2)
        << "vertex " << v << ", angle defect " << defect;
  }
  EXPECT_EQ(sum, 4 * m.euler_characteristic());
  // A face with one feature or boundary edge holds a cross along it, on the field's surface.
  uint32_t checked = 0;
  for (uint32_t f = 0; f < m.num_faces(); ++f) {
    uint32_t edges = 0, along = kInvalid;
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t h = 3 * f + i;
      if (m.twin(h) == kInvalid || cf.feature[m.edge(h)]) ++edges, along = h;
    }
    if (edges != 1) continue;
    ++checked;
    const Vec3 d =
        cf.surface.position(cf.surface.to(along)) - cf.surface.position(cf.surface.from(along));
    const double off = std::remainder(cf.frames.arg(f, d) - cf.angle[f], std::numbers::pi / 2);
    EXPECT_LT(std::abs(off), 1e-9) << "face " << f;
  }
  EXPECT_EQ(checked > 0, cf.constrained_faces > 0);
  if (m.num_faces() <= 15000) {
    const Field again = field_of(p);
    EXPECT_EQ(again.cf.angle.values(), cf.angle.values());
  }
}

// Every interior node emits as many separatrices as its index asks (4 - 4I: 3 at a +1/4
// singularity, 5 at a -1/4 one, 4 at a seed): counted as the crossings of the field's arms
// around the node, an arm in the gap between two faces' copies of the field is found, and one
// in both is counted once. Read per face sector, up to 43 singularities of a mesh (the
// elephant's; fandisk 4) were short of a ray or had one too many, and their patches turned by
// three quarters there (`isoquad field --json`, ray_mismatches).
TEST_P(CorpusField, EveryInteriorNodeEmitsTheRaysItsIndexCounts) {
  ISOQUAD_CORPUS_MESH(path, GetParam());
  const Field field = field_of(prepare(read_mesh(path).mesh));
  const CrossField& cf = field.cf;
  TraceOptions o;
  o.edge_length = edge_length_for_quads(field.refined.mesh, 1500);
  const TraceResult r = trace_separatrices(cf, o);
  // A singularity of index +1 or more (4 - 4I <= 0: the field turns a whole turn around it, as
  // at one vertex of cactus and of the cow on their unsubdivided surfaces) has no count of rays
  // to meet; it emits what its sectors hold and is counted as a mismatch.
  uint32_t whole_turns = 0;
  for (uint32_t v : cf.singular) whole_turns += cf.index4[v] >= 4;
  EXPECT_LE(r.ray_mismatches, whole_turns);
}

// A trace that runs onto a vertex circles its one-ring in steps of zero length, and one caught in
// a limit cycle (round the vortex the cow's field makes at a sharp tip) goes round and round: the
// first ends there as a sink, the second as capped once it crosses a face the eighth time. Before,
// the first circled for two steps per face of the surface (47,000 on the cow's subdivided surface,
// each scanning the segments left in the faces around: 17 of the 18 s its coarse layout took), the
// second until it was 141 h long.
TEST_P(CorpusField, NoTraceGoesRoundInCircles) {
  ISOQUAD_CORPUS_MESH(path, GetParam());
  const Field field = field_of(prepare(read_mesh(path).mesh));
  TraceOptions o;
  o.edge_length = edge_length_for_quads(field.refined.mesh, 1500);
  const TraceResult r = trace_separatrices(field.cf, o);
  for (uint32_t id = 0; id < r.traces.size(); ++id) {
    std::unordered_map<uint32_t, uint32_t> visits;
    uint32_t most = 0;
    for (uint32_t f : r.traces[id].faces) most = std::max(most, ++visits[f]);
    EXPECT_LE(most, 8u) << "trace " << id << " from vertex " << r.traces[id].source;
  }
}

INSTANTIATE_TEST_SUITE_P(Corpus, CorpusField, testing::ValuesIn(test::kCorpusMeshes),
                         [](const testing::TestParamInfo<const char*>& info) {
                           return test::corpus_case_name(info.param, 0);
                         });

TEST(CorpusFieldTotal, FewerSingularitiesThanTheIrregularVerticesAllowed) {
  std::size_t total = 0;
  for (const char* file : test::kCorpusMeshes) {
    ISOQUAD_CORPUS_MESH(path, file);
    total += field_of(prepare(read_mesh(path).mesh)).cf.singular.size();
  }
  // A regression bound: 649 with the smoothing at h (817 without it). The layout issue's aim is
  // at most 457 irregular vertices in the end (60% of the VSA layout's 762), which the pair
  // cancellation and the layout's simplification are to reach.
  EXPECT_LE(total, 700u);
}

namespace {

struct LaidOut {
  RemeshRun run;
  QualityReport quality;
};

// The field mode's run at `quads`, as it is: no assertion on its output.
RemeshRun field_run(const ReadResult& input, double quads) {
  RemeshOptions o;
  o.quads = quads;
  o.segmentation = "field";
  return remesh_run(input.mesh, o, input.unshared_vertices);
}

LaidOut remesh_with(const ReadResult& input, const std::string& segmentation) {
  RemeshOptions o;
  o.quads = 1500;
  o.segmentation = segmentation;
  LaidOut out{remesh_run(input.mesh, o, input.unshared_vertices), {}};
  out.quality = measure_quality(out.run.result.quads, &input.mesh);
  // Whatever made the patches, the output is valid.
  EXPECT_TRUE(out.quality.pure_quad);
  EXPECT_TRUE(out.quality.edge_manifold);
  EXPECT_TRUE(out.quality.vertex_manifold);
  EXPECT_TRUE(out.quality.same_topology);
  EXPECT_EQ(out.quality.sj_surface_nonpositive, 0u);
  EXPECT_EQ(out.quality.sj_invalid, 0u) << "scaled Jacobian <= 0.001 against the own normal";
  EXPECT_NEAR(double(out.run.result.quads.num_faces()), 1500, 150);
  return out;
}

}  // namespace

// The cylinder (open, its two rims creases of the field): one traced patch, its corners where the
// rims' seam meets them. The field's quads follow the rulings where VSA's patches bend them.
TEST(CorpusFieldLayout, CylinderIsLaidOutAlongItsRulings) {
  ISOQUAD_CORPUS_MESH(path, "cylinder.off");
  const ReadResult input = read_mesh(path);
  const LaidOut field = remesh_with(input, "field");
  ASSERT_EQ(field.run.runs.size(), 1u);
  const ComponentRun& r = field.run.runs[0];
  EXPECT_TRUE(r.field_used) << r.field_log.failure;
  EXPECT_TRUE(r.field_log.failure.empty());
  EXPECT_EQ(r.field_corners.size(), r.seg.num_patches);
  EXPECT_EQ(field.quality.irregular, 0u);
  const LaidOut vsa = remesh_with(input, "vsa");
  EXPECT_FALSE(vsa.run.runs[0].field_used);
  EXPECT_LT(field.quality.angle_deviation_max, 1.0);
  EXPECT_LT(field.quality.angle_deviation_max, vsa.quality.angle_deviation_max);
  EXPECT_LE(field.quality.edge_cv, vsa.quality.edge_cv);
  // The report says which segmentation made the quads.
  const auto report = nlohmann::json::parse(field.run.result.report);
  EXPECT_EQ(report["components"][0]["layout_source"], "field");
  EXPECT_EQ(report["options"]["segmentation"], "field");
}

// The sphere: its eight +1/4 singularities joined by twelve separatrices, each found from one end
// and steered into the other (traced from both ends, they pass a triangle apart and leave a
// sliver), cut it into the six faces of a cube. Every corner is the traces', every quad is
// nearly square, and the only irregular vertices are the singularities.
TEST(CorpusFieldLayout, SphereIsLaidOutAsACube) {
  ISOQUAD_CORPUS_MESH(path, "sphere.off");
  const ReadResult input = read_mesh(path);
  const LaidOut field = remesh_with(input, "field");
  const ComponentRun& r = field.run.runs[0];
  ASSERT_TRUE(r.field_used) << r.field_log.failure;
  EXPECT_EQ(r.field_log.singularities, 8u);
  EXPECT_EQ(r.field_log.connections, 12u);
  EXPECT_EQ(r.seg.num_patches, 6u);
  EXPECT_EQ(r.field_log.free_corner_patches, 0u);
  EXPECT_EQ(field.quality.irregular, 8u);
  EXPECT_EQ(field.quality.sj_nonpositive, 0u);
  EXPECT_GT(field.quality.sj_min, 0.5);
  EXPECT_GT(field.quality.sj_mean, 0.97);
  const LaidOut vsa = remesh_with(input, "vsa");
  EXPECT_GT(field.quality.sj_mean, vsa.quality.sj_mean);
  EXPECT_LT(field.quality.edge_cv, vsa.quality.edge_cv);
}

// The knot: a tube with no singularity and no feature, so no trace, and one patch that is a
// torus. Two seeds far apart close a loop around the tube each and join along it: four disks, and
// a quad mesh without an irregular vertex (VSA's blobs leave about a hundred).
TEST(CorpusFieldLayout, KnotIsCutByTheLoopsOfTwoSeeds) {
  ISOQUAD_CORPUS_MESH(path, "knot1.off");
  const ReadResult input = read_mesh(path);
  const LaidOut field = remesh_with(input, "field");
  const ComponentRun& r = field.run.runs[0];
  ASSERT_TRUE(r.field_used) << r.field_log.failure;
  EXPECT_EQ(r.field_log.singularities, 0u);
  EXPECT_EQ(r.field_log.seeds, 2u);
  EXPECT_EQ(r.seg.num_patches, 4u);
  EXPECT_EQ(r.field_log.free_corner_patches, 0u);
  EXPECT_EQ(field.quality.irregular, 0u);
  EXPECT_EQ(field.quality.sj_nonpositive, 0u);
  EXPECT_GT(field.quality.sj_mean, 0.95);
  EXPECT_GT(field.quality.sj_min, 0.5);
}

// Where the traced patches cannot be used (here mech-holes-shark: its traced quads keep one with
// scaled Jacobian <= 0.001 against its own normal; before, the locked map crowded a thin traced
// patch to zero area), the component takes VSA's patches with VSA's repairs, as
// `--segmentation vsa` would, and the report says why.
TEST(CorpusFieldLayout, FailedFieldLayoutFallsBackToVsaAndSaysWhy) {
  ISOQUAD_CORPUS_MESH(path, "mech-holes-shark.off");
  const ReadResult input = read_mesh(path);
  const LaidOut field = remesh_with(input, "field");
  const ComponentRun& r = field.run.runs[0];
  EXPECT_FALSE(r.field_used);
  EXPECT_FALSE(r.field_log.failure.empty());
  EXPECT_GT(r.field_log.traces, 0u);
  const auto report = nlohmann::json::parse(field.run.result.report);
  EXPECT_EQ(report["components"][0]["layout_source"], "vsa");
  EXPECT_EQ(report["components"][0]["field"]["fallback_reason"], r.field_log.failure);
  const LaidOut vsa = remesh_with(input, "vsa");
  EXPECT_EQ(field.run.result.quads.positions, vsa.run.result.quads.positions);
}

// The hand at 700 quads: its traced layout mapped, but the untangler left quads at its fingers
// with scaled Jacobian <= 0.001 against their own normal or folded against the surface (2 and 5
// of 1,484 when measured). Field mode keeps the promise of a valid output all the same: a
// component whose traced quads are not all valid takes VSA's patches, and the report says why.
TEST(CorpusFieldLayout, TracedQuadsThatAreNotValidAreNotKept) {
  ISOQUAD_CORPUS_MESH(path, "hand.off");
  const ReadResult input = read_mesh(path);
  const RemeshRun run = field_run(input, 700);
  ASSERT_EQ(run.runs.size(), 1u);
  const ComponentRun& r = run.runs[0];
  const QualityReport q = measure_quality(run.result.quads, &input.mesh);
  EXPECT_TRUE(q.pure_quad && q.edge_manifold && q.vertex_manifold && q.oriented);
  EXPECT_TRUE(q.same_topology);
  EXPECT_EQ(q.sj_surface_nonpositive, 0u);
  EXPECT_EQ(q.sj_invalid, 0u) << "scaled Jacobian <= 0.001 against the own normal";
  EXPECT_NEAR(double(run.result.quads.num_faces()), 700, 70);
  const auto report = nlohmann::json::parse(run.result.report);
  EXPECT_EQ(report["components"][0]["layout_source"], r.field_used ? "field" : "vsa");
  if (!r.field_used) {
    EXPECT_FALSE(r.field_log.failure.empty());
    EXPECT_EQ(report["components"][0]["field"]["fallback_reason"], r.field_log.failure);
  }
}

namespace {

// The traced patches whose corners the layout changed: each had one corner slid to a
// neighbouring meta-vertex of its cycle, over a meta-edge shorter than a quad.
uint32_t expect_slid_only_over_short_edges(const ComponentRun& r) {
  const MetaMesh& meta = r.seg.meta;
  const double h = r.layout.edge_length;
  uint32_t slid = 0;
  for (uint32_t p = 0; p < r.field_corners.size(); ++p) {
    const auto& given = r.field_corners[p];
    if (given == kFreeCorners || r.field_preferred[p]) continue;
    std::array<uint32_t, 4> chosen = r.layout.charts[p].corners;
    std::sort(chosen.begin(), chosen.end());
    if (chosen == given) continue;
    ++slid;
    std::vector<uint32_t> gone, added;
    std::set_difference(given.begin(), given.end(), chosen.begin(), chosen.end(),
                        std::back_inserter(gone));
    std::set_difference(chosen.begin(), chosen.end(), given.begin(), given.end(),
                        std::back_inserter(added));
    EXPECT_EQ(gone.size(), 1u) << "patch " << p;
    EXPECT_EQ(added.size(), 1u) << "patch " << p;
    if (gone.size() != 1 || added.size() != 1) continue;
    const auto& cycle = meta.faces[p].cycle;
    const uint32_t m = uint32_t(cycle.size());
    const bool forward = added[0] == (gone[0] + 1) % m, backward = gone[0] == (added[0] + 1) % m;
    EXPECT_TRUE(forward || backward) << "patch " << p;
    const uint32_t over = cycle[forward ? gone[0] : added[0]].edge;
    EXPECT_LT(meta.edges[over].geodesic, h) << "patch " << p;
  }
  return slid;
}

}  // namespace

// bunny00: with every node's rays counted as crossings, the traces' rules give nearly every
// patch its four corners (at most 3 left to the corner ILP; with rays read per face sector, 9
// patches of five or three corners, whose corners the ILP chose from their shapes: mean scaled
// Jacobian 0.852 and 24% of the quads with aspect ratio above 2). Measured: 0.910 and 10.9%
// (0.908 and 9.4% before the coarse layout deleted one trace).
TEST(CorpusFieldLayout, TracedPatchesHaveTheirFourCornersFromTheTraces) {
  ISOQUAD_CORPUS_MESH(path, "bunny00.off");
  const ReadResult input = read_mesh(path);
  const RemeshRun run = field_run(input, 1500);
  const ComponentRun& r = run.runs[0];
  ASSERT_TRUE(r.field_used) << r.field_log.failure;
  EXPECT_LE(r.field_log.free_corner_patches, 3u);
  expect_slid_only_over_short_edges(r);
  const QualityReport q = measure_quality(run.result.quads, &input.mesh);
  EXPECT_TRUE(q.pure_quad && q.edge_manifold && q.vertex_manifold && q.same_topology);
  EXPECT_EQ(q.sj_surface_nonpositive, 0u);
  EXPECT_EQ(q.sj_invalid, 0u);
  EXPECT_GT(q.sj_mean, 0.875);
  EXPECT_LT(q.aspect_above_2, 12.0);  // percent
}

// Cactus: its short creases, none sharper than 80 degrees on average, do not pin the field. When
// they did: 46 singularities, mean SJ 0.858 and 31% of the quads above aspect 2; measured without
// them: 24, 0.949 and 1.4%.
TEST(CorpusFieldLayout, WeakShortCreasesDoNotPinTheField) {
  ISOQUAD_CORPUS_MESH(path, "cactus.off");
  const ReadResult input = read_mesh(path);
  const RemeshRun run = field_run(input, 1500);
  const ComponentRun& r = run.runs[0];
  ASSERT_TRUE(r.field_used) << r.field_log.failure;
  EXPECT_LE(r.field_log.singularities, 30u);
  const QualityReport q = measure_quality(run.result.quads, &input.mesh);
  EXPECT_TRUE(q.pure_quad && q.edge_manifold && q.vertex_manifold && q.same_topology);
  EXPECT_EQ(q.sj_surface_nonpositive, 0u);
  EXPECT_EQ(q.sj_invalid, 0u);
  EXPECT_NEAR(double(run.result.quads.num_faces()), 1500, 150);
  EXPECT_GT(q.sj_mean, 0.93);
  EXPECT_LT(q.aspect_above_2, 5.0);  // percent
  EXPECT_LT(q.hausdorff, 0.01);      // of the diagonal
}

// three_peaks and the armadillo: where the side equations of the traced corners admit no
// positive lengths, the layout slides, and only over meta-edges shorter than a quad, where a
// trace stopped a fraction of a quad from a node or another trace's end (2 patches each when
// measured; the double torus slid before the coarse layout took its short meta-edges away).
// Which of the two slides depends on OpenBLAS's kernels (three_peaks with SkylakeX's and
// Cooperlake's, the armadillo with Haswell's: docs/threads.md), so both are run and at least one
// must slide.
TEST(CorpusFieldLayout, CornersSlideOverMetaEdgesShorterThanAQuad) {
  uint32_t slid = 0;
  for (const char* file : {"three_peaks.off", "armadillo.off"}) {
    SCOPED_TRACE(file);
    ISOQUAD_CORPUS_MESH(path, file);
    const ReadResult input = read_mesh(path);
    const LaidOut field = remesh_with(input, "field");
    const ComponentRun& r = field.run.runs[0];
    ASSERT_TRUE(r.field_used) << r.field_log.failure;
    const uint32_t here = expect_slid_only_over_short_edges(r);
    EXPECT_EQ(here > 0, std::any_of(r.layout_report.repairs.begin(), r.layout_report.repairs.end(),
                                    [](const std::string& s) {
                                      return s.find("slid") != std::string::npos;
                                    }));
    slid += here;
  }
  EXPECT_GE(slid, 1u);
}

namespace {

// The field-aligned patches of a corpus mesh's first component at the size of 1,500 quads.
FieldSegmentation field_layout_at_1500(const std::string& path, FieldLayoutLog& log) {
  const PreparedMesh p = prepare(read_mesh(path).mesh);
  const PreparedComponent& c = p.components.at(0);
  return field_segment(c.mesh, c.feature, edge_length_for_quads(c.mesh, 1500), log);
}

}  // namespace

// The armadillo's traces leave a patch that is a narrow ring round an island patch (the loop of
// a trace closing on itself round a small region): too narrow for the two-path cut, and the
// Voronoi split, seeded along the ring's long tail, kept a ring. The island joins the ring, and
// every patch is a disk.
TEST(CorpusFieldLayout, AnIslandInANarrowRingJoinsIt) {
  ISOQUAD_CORPUS_MESH(path, "armadillo.off");
  FieldLayoutLog log;
  const FieldSegmentation fs = field_layout_at_1500(path, log);
  ASSERT_TRUE(log.failure.empty()) << log.failure;
  EXPECT_GE(fs.seg.repair.islands_merged, 1u);
  const auto topo = patch_topology(fs.seg.refined.mesh, fs.seg.labels, fs.seg.num_patches);
  for (uint32_t q = 0; q < topo.size(); ++q) EXPECT_TRUE(topo[q].is_disk()) << "patch " << q;
}

class CorpusCoarseLayout : public testing::TestWithParam<const char*> {};

// The coarse layout (FIELD_LAYOUT.md §5) deletes traces only where the layout's misfit drops by
// kCoarseGain or more, and never leaves more patches without their four traced corners; it stops
// within its budget of traced layouts.
TEST_P(CorpusCoarseLayout, DeletesOnlyWhereTheMisfitDropsAndCornersStay) {
  ISOQUAD_CORPUS_MESH(path, GetParam());
  FieldLayoutLog log;
  const FieldSegmentation fs = field_layout_at_1500(path, log);
  ASSERT_TRUE(log.failure.empty()) << log.failure;
  EXPECT_EQ(fs.corners.size(), log.patches);
  EXPECT_LE(log.coarse_evaluations, kCoarseEvaluations);
  EXPECT_LE(log.free_corner_patches, log.free_corner_patches_traced);
  EXPECT_LE(log.misfit, log.misfit_traced);
  if (log.coarse_deleted > 0)
    EXPECT_LE(log.misfit, log.misfit_traced - kCoarseGain);
  else
    EXPECT_EQ(log.misfit, log.misfit_traced);
}

INSTANTIATE_TEST_SUITE_P(Corpus, CorpusCoarseLayout,
                         testing::Values("anchor.off", "fandisk.off", "nefertiti.off", "eight.off",
                                         "three_peaks.off"),
                         [](const testing::TestParamInfo<const char*>& info) {
                           return test::corpus_case_name(info.param, 0);
                         });

// anchor: its traced layout has 120 patches, many of them strips and slivers between traces that
// stop a fraction of a quad apart, whose meta-edges the integer lengths stretch to whole quads
// (mean scaled Jacobian 0.680, 46.9% of the quads above aspect 2, 1.92% from the surface). The
// coarse layout deletes their traces (31 rays, 87 patches when measured): 0.753, 20.1%, 1.26%.
TEST(CorpusFieldLayout, CoarseLayoutMergesTheStripsOfTheAnchor) {
  ISOQUAD_CORPUS_MESH(path, "anchor.off");
  const ReadResult input = read_mesh(path);
  const LaidOut field = remesh_with(input, "field");
  const ComponentRun& r = field.run.runs[0];
  ASSERT_TRUE(r.field_used) << r.field_log.failure;
  EXPECT_GE(r.field_log.coarse_deleted, 10u);
  EXPECT_LT(r.field_log.patches, r.field_log.patches_traced);
  EXPECT_GT(field.quality.sj_mean, 0.72);
  EXPECT_LT(field.quality.aspect_above_2, 30.0);  // percent
  EXPECT_LT(field.quality.hausdorff, 0.015);      // of the diagonal
}
