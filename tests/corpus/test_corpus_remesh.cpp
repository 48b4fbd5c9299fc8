// The whole method on every corpus mesh at 1,500 quads: the output is pure quad, edge- and
// vertex-manifold, consistently oriented, and has the input's components, boundary loops and
// Euler characteristic; its quad count is what the layout promised and within 10% of the
// request. Untangling never adds folds, no quad folds against the surface (52 quads over the
// corpus once), no quad has a scaled Jacobian <= 0.001 against its own normal and the Hausdorff
// distance is within 2% of the diagonal.
// The run's report folder (pictures, layout, JSON, HTML) is complete and its numbers are the
// output's quality.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cstdio>
#include <iterator>

#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "corpus.hpp"
#include "io/read_mesh.hpp"
#include "io/report_json.hpp"
#include "metrics/aabb_tree.hpp"
#include "metrics/quality.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/remesh.hpp"
#include "pipeline/sizing.hpp"
#include "prep/prepare.hpp"
#include "quad_checks.hpp"
#include "report/report.hpp"
#include "report_checks.hpp"

using namespace isoquad;

namespace {
class CorpusRemesh : public testing::TestWithParam<const char*> {};

// The shortest quad edge over the bounding-box diagonal: 0 means two corners coincide (a
// degenerate element that no scaled Jacobian threshold sees as worse than a fold).
double shortest_edge(const PolyMesh& quads) {
  Box3 box;
  for (const Vec3& p : quads.positions) box.add(p);
  double shortest = INFINITY;
  for (std::size_t f = 0; f < quads.num_faces(); ++f) {
    const auto vs = quads.face(f);
    for (std::size_t i = 0; i < vs.size(); ++i)
      shortest = std::min(shortest,
                          norm(quads.positions[vs[i]] - quads.positions[vs[(i + 1) % vs.size()]]));
  }
  return shortest / box.diagonal();
}

// Quads with a scaled Jacobian <= 0.001 against their own normal (kMinValidScaledJacobian),
// which validity forbids, that runs here still leave: by corpus mesh and quad count asked for.
// Since the untangler counts a corner by the lower of its surface and own-normal values, the
// VSA runs at 1,500 quads and at the default size have none (46 quads on 11 meshes and 52 on 9
// before, each a quad bent across a crease or a sharp fold with a reflex corner in its own
// plane). With four-sided patches forced (--split-patches), fandisk and mech-holes-shark keep
// some at 180-degree crease corners that no move, collapse or split removes (measured
// 2026-12-07: 11 and 15; 16 and 19 before), and some of those fold against the surface too,
// which that test does not assert either. Every other run here must have none, these no more.
struct KnownInvalid {
  const char* mesh;
  double quads;
  uint32_t count;
};
constexpr KnownInvalid kKnownInvalid[] = {
    {"fandisk.off --split-patches", 1500, 11},
    {"mech-holes-shark.off --split-patches", 1500, 15},
};

// No quad not valid against its own normal, or no more than the known ones.
void expect_valid_against_own_normal(const QualityReport& q, const std::string& mesh,
                                     double quads) {
  uint32_t known = 0;
  for (const KnownInvalid& k : kKnownInvalid)
    if (k.mesh == mesh && k.quads == quads) known = k.count;
  EXPECT_LE(q.sj_invalid, known) << mesh << " at " << quads
                                 << " quads: quads with scaled Jacobian <= 0.001 against their own "
                                 << "normal (min " << q.sj_min << "; " << q.sj_surface_nonpositive
                                 << " folded against the surface)";
  testing::Test::RecordProperty("sj_invalid", int(q.sj_invalid));
}

// The output's quality against the input, and the validity every output must have: pure quad,
// manifold, of the input's topology, no quad folded against the surface nor (but the known ones)
// against its own normal. `quads`: the count asked for (0: the default size).
QualityReport expect_valid_output(const PolyMesh& quads, const ReadResult& input,
                                  const std::string& mesh, double asked) {
  const QualityReport q = measure_quality(quads, &input.mesh);
  EXPECT_TRUE(q.pure_quad);
  EXPECT_TRUE(q.edge_manifold);
  EXPECT_TRUE(q.vertex_manifold);
  EXPECT_TRUE(q.same_topology);
  EXPECT_EQ(q.sj_surface_nonpositive, 0u);
  expect_valid_against_own_normal(q, mesh, asked);
  return q;
}

// A run at the default size with one later step turned off by `off`, on one component, and its
// distance to the input: what the test of that step compares the default run with.
struct Without {
  RemeshRun run;
  QualityReport quality;
};
Without remesh_without(const ReadResult& input, void (*off)(RemeshOptions&)) {
  RemeshOptions o;
  off(o);
  Without w{remesh_run(input.mesh, o, input.unshared_vertices), {}};
  EXPECT_EQ(w.run.runs.size(), 1u);
  w.quality = measure_quality(w.run.result.quads, &input.mesh);
  return w;
}

// Each run with tips split is kept only when it is closer than the run kept before it with no
// more folds. Each run starts from the kept run, or from the run before it when that was not
// kept (unless it added several tips to the kept run: then the rounds go back to the kept run
// and from then on add one tip at a time), and has more tips than the run it starts from. The
// kept run's figures are the output's (one component: its distance is sampled on the prepared
// surface, so it matches `quality`'s, sampled on the input, to the sampling's noise: a few
// percent).
// Local refinement follows where the kept quads are beyond the distance target (1% of the
// diagonal) or fold: its first figures are those quads. A round is kept over them only with
// fewer folds, or as many and within the target or (`counted`: a count asked for) nearer than
// kRefineGain of the first; over a round kept before it only with fewer folds, or as many and
// nearer. A round within the target with no fold is the last, and so is a round past `most`
// quads (1.1 times the count asked for, or twice the first), never kept. The kept figures are
// the output's.
const SizeRound& expect_refine_kept_only_if_better(const ComponentRun& r, const SizeRound& before,
                                                   double most, bool counted) {
  if (r.refine_rounds.empty()) return before;
  const auto& rounds = r.refine_rounds;
  const SizeRound& first = rounds[0].result;
  EXPECT_EQ(rounds[0].marked, 0u);
  EXPECT_EQ(first.quads, before.quads);
  EXPECT_EQ(first.folded, before.folded);
  EXPECT_DOUBLE_EQ(first.distance, before.distance);
  EXPECT_TRUE(first.distance > kTipTarget || first.folded > 0);
  EXPECT_LE(rounds.size(), 1 + kRefineRounds);
  std::size_t kept = 0;
  for (std::size_t k = 1; k < rounds.size(); ++k) {
    const SizeRound& now = rounds[k].result;
    EXPECT_GT(rounds[k].marked, 0u);
    EXPECT_GT(now.quads, rounds[k - 1].result.quads);
    if (double(now.quads) > most) {
      EXPECT_EQ(k + 1, rounds.size()) << "a round past the count is the last";
      continue;
    }
    const SizeRound& best = rounds[kept].result;
    const bool better = kept > 0
                            ? now.folded < best.folded ||
                                  (now.folded == best.folded && now.distance < best.distance)
                            : now.folded < first.folded ||
                                  (now.folded == first.folded &&
                                   (now.distance <= kTipTarget ||
                                    (counted && now.distance <= kRefineGain * first.distance)));
    if (better) kept = k;
    if (better && now.distance <= kTipTarget && now.folded == 0) {
      EXPECT_EQ(k + 1, rounds.size()) << "a round within the target with no fold is the last";
    }
  }
  EXPECT_EQ(r.refine_round_kept, kept);
  return rounds[r.refine_round_kept].result;
}

// `asked`: the quad count asked for, 0 for the default size.
void expect_tip_split_kept_only_if_better(const RemeshRun& run, const QualityReport& q,
                                          double asked) {
  for (const ComponentRun& r : run.runs) {
    const double most =
        asked > 0
            ? kRefineGrowthSized * asked * r.area_share
            : kRefineGrowth * double(r.refine_rounds.empty() ? 0 : r.refine_rounds[0].result.quads);
    if (r.tip_rounds.empty()) {
      EXPECT_TRUE(r.tips.empty());
      if (!r.refine_rounds.empty()) {
        const SizeRound& result =
            expect_refine_kept_only_if_better(r, r.refine_rounds[0].result, most, asked > 0);
        EXPECT_EQ(result.quads, r.quads.quads.size());
        EXPECT_EQ(result.folded, r.untangle_report.nonpositive);
      }
      continue;
    }
    const auto& rounds = r.tip_rounds;
    ASSERT_GE(rounds.size(), 2u);
    ASSERT_LE(rounds.size(), 1 + kTipRounds);
    EXPECT_EQ(rounds[0].tips, 0u);
    std::size_t kept = 0, from = 0;
    bool one_at_a_time = false;
    for (std::size_t k = 1; k < rounds.size(); ++k) {
      const SizeRound &now = rounds[k].result, &best = rounds[kept].result;
      EXPECT_GT(rounds[k].tips, rounds[from].tips);
      const uint32_t added = rounds[k].tips - rounds[from].tips;
      if (one_at_a_time) {
        EXPECT_EQ(added, 1u);
      }
      if (now.distance < best.distance && now.folded <= best.folded) {
        kept = from = k;
      } else if (from == kept && added >= 2 && !one_at_a_time) {
        one_at_a_time = true;
      } else {
        from = k;
      }
    }
    EXPECT_EQ(r.tip_round_kept, kept);
    const SizeRound& result =
        expect_refine_kept_only_if_better(r, rounds[kept].result, most, asked > 0);
    EXPECT_EQ(r.tips.size(), rounds[kept].tips);
    EXPECT_EQ(result.quads, r.quads.quads.size());
    EXPECT_EQ(result.folded, r.untangle_report.nonpositive);
    if (run.runs.size() == 1) {
      EXPECT_NEAR(result.distance, q.hausdorff, 0.1 * q.hausdorff);
    }
  }
}

// Per quad, the lower of its scaled Jacobians against the surface and against its own normal,
// as `quality` measures them: at or below 0, the quad folds (the untangler's measure).
std::vector<double> lower_scaled_jacobians(const PolyMesh& quads, const ReadResult& input) {
  std::vector<double> sj = surface_scaled_jacobians(quads, input.mesh);
  for (std::size_t f = 0; f < quads.num_faces(); ++f) {
    const auto v = quads.face(f);
    const auto& x = quads.positions;
    sj[f] = std::min(sj[f], quad_scaled_jacobian({x[v[0]], x[v[1]], x[v[2]], x[v[3]]}));
  }
  return sj;
}

// Quads folded against the surface or their own normal (lower_scaled_jacobians at or below 0).
uint32_t folded_quads(const PolyMesh& quads, const ReadResult& input) {
  const std::vector<double> sj = lower_scaled_jacobians(quads, input);
  return uint32_t(std::count_if(sj.begin(), sj.end(), [](double s) { return s <= 0; }));
}

// A folded quad left in the output is said, with its count and where: the point named is the
// centre of a quad folded against the surface or its own normal, as `quality` measures them;
// with no fold left, nothing is said.
void expect_folds_said(const std::vector<std::string>& said, const PolyMesh& quads,
                       const ReadResult& input) {
  const std::vector<double> sj = lower_scaled_jacobians(quads, input);
  const uint32_t folded = folded_quads(quads, input);
  const auto warning = std::find_if(said.begin(), said.end(), [](const std::string& s) {
    return s.find("still fold") != std::string::npos;
  });
  EXPECT_EQ(warning != said.end(), folded > 0);
  if (warning == said.end()) return;
  EXPECT_NE(warning->find(std::to_string(folded) + " quad"), std::string::npos) << *warning;
  Vec3 near;
  const std::size_t at = warning->find("near (");
  ASSERT_NE(at, std::string::npos) << *warning;
  ASSERT_EQ(std::sscanf(warning->c_str() + at, "near (%lf, %lf, %lf)", &near.x, &near.y, &near.z),
            3)
      << *warning;
  std::size_t closest = 0;
  double best = INFINITY;
  for (std::size_t f = 0; f < quads.num_faces(); ++f) {
    Vec3 c;
    for (const uint32_t v : quads.face(f)) c = c + 0.25 * quads.positions[v];
    if (norm(c - near) < best) best = norm(c - near), closest = f;
  }
  EXPECT_LE(sj[closest], 0.0) << "the quad named, near " << *warning;
}

// Patch rounds follow where the run (after its tips and refinement) is beyond the distance
// target: each with more VSA patches than the one before. A round is kept over the round kept
// before it within 1.1 times the count asked for (`asked`; 0: the default size) with fewer folds,
// or with as many and within the target or, with a count asked for, nearer than kRefineGain of
// it; a kept
// round within the target is the last, and so is, within a count, a round not kept. The kept
// round's figures and patches are the output's.
void expect_patch_rounds_kept_only_if_better(const RemeshRun& run, double asked) {
  for (const ComponentRun& r : run.runs) {
    if (r.patch_rounds.empty()) continue;
    const auto& rounds = r.patch_rounds;
    EXPECT_GT(rounds[0].result.distance, kTipTarget);
    EXPECT_LE(rounds.size(), 1 + std::size(kPatchGrowth));
    std::size_t kept = 0;
    for (std::size_t k = 1; k < rounds.size(); ++k) {
      const SizeRound &now = rounds[k].result, &best = rounds[kept].result;
      EXPECT_GT(rounds[k].patches, rounds[k - 1].patches);
      const bool within = asked <= 0 || double(now.quads) <= kCountSlack * asked * r.area_share;
      if (within && (now.folded < best.folded ||
                     (now.folded == best.folded &&
                      (now.distance <= kTipTarget ||
                       (asked > 0 && now.distance <= kRefineGain * best.distance)))))
        kept = k;
      if (kept == k && now.distance <= kTipTarget) {
        EXPECT_EQ(k + 1, rounds.size()) << "a round within the target is the last";
      }
      if (kept != k && asked > 0) {
        EXPECT_EQ(k + 1, rounds.size()) << "within a count, a round not kept is the last";
      }
    }
    EXPECT_EQ(r.patch_round_kept, kept);
    EXPECT_EQ(r.seg.vsa_patches, rounds[kept].patches);
    EXPECT_EQ(rounds[kept].result.quads, r.quads.quads.size());
    EXPECT_EQ(rounds[kept].result.folded, r.untangle_report.nonpositive);
  }
}

// The median meta-edge is laid out near its geodesic length: the layout neither coarsens nor
// refines the mesh as a whole (the elephant's default size had 4.5 before the request was
// raised to the count the patches allow; 0.97-1.34 over the corpus since).
void expect_lengths_near_targets(const RemeshRun& run) {
  for (const ComponentRun& r : run.runs) {
    const std::vector<double> ratio = r.layout.length_ratios();
    ASSERT_FALSE(ratio.empty());
    const double median = ratio[ratio.size() / 2];
    EXPECT_GT(median, 0.8);
    EXPECT_LT(median, 1.5);
  }
}
}  // namespace

TEST_P(CorpusRemesh, ValidPureQuadMeshOfTheSameTopology) {
  ISOQUAD_CORPUS_MESH(path, GetParam());
  const ReadResult input = read_mesh(path);
  RemeshOptions o;
  o.quads = 1500;
  std::vector<std::string> said;
  const RemeshRun run = remesh_run(input.mesh, o, input.unshared_vertices,
                                   [&](const std::string& s) { said.push_back(s); });
  const PreparedMesh& prep = run.prep;
  const PolyMesh& quads = run.result.quads;
  int64_t promised = 0;
  for (const ComponentRun& r : run.runs) {
    // Every quad of the layout (or of its refinement, when kept), less those the untangler's
    // diagonal collapses removed, plus four for each quad it split in five.
    EXPECT_EQ(r.extract_report.quads == r.layout.quads(), r.refine_round_kept == 0);
    promised += int64_t(r.extract_report.quads) - r.untangle_report.collapsed -
                r.untangle_report.doublets + 4 * r.untangle_report.split;
    // The verifier: a certified map covers every lattice point once.
    EXPECT_EQ(r.extract_report.multiply_covered, 0u);
    EXPECT_EQ(r.extract_report.patches_locked, 0u);
    EXPECT_LE(r.untangle_report.folded_after, r.untangle_report.folded_before);
    EXPECT_GE(r.untangle_report.min_after, r.untangle_report.min_before);
    // Tip snapping never takes a surface vertex farther from the quads.
    EXPECT_LE(r.snap_report.farthest_after, r.snap_report.farthest_before);
    // Where the quads folded (the cow's one in its 107-patch run), refinement cut them finer until
    // none did, within the count asked for.
    if (!r.refine_rounds.empty() && r.refine_rounds[0].result.folded > 0) {
      EXPECT_EQ(r.refine_rounds[r.refine_round_kept].result.folded, 0u);
    }
  }
  EXPECT_EQ(int64_t(quads.num_faces()), promised);
  expect_lengths_near_targets(run);
  const QualityReport q = measure_quality(quads, &input.mesh);
  test::expect_valid_quad_mesh(q);
  EXPECT_NEAR(double(quads.num_faces()), 1500.0, 150.0);
  expect_tip_split_kept_only_if_better(run, q, 1500);
  expect_patch_rounds_kept_only_if_better(run, 1500);
  EXPECT_GT(shortest_edge(quads), 1e-6);
  // No quad folded against the surface (the cow's last one went with the refinement of folded
  // quads; the anchor's with the flips of its needles, the hand's with the supernodal
  // factorization's rounding).
  EXPECT_EQ(q.sj_surface_nonpositive, 0u);
  expect_valid_against_own_normal(q, GetParam(), 1500);
  // The armadillo is farthest, 1.37% (1.49% with OpenBLAS's SkylakeX kernels; 3.81% at its
  // fingers and toes before the tip splits, 2.89% with one round). The cow is at 0.91% with the
  // patch rounds (2.03% before, its chest and udder bridged by stretched quads; 3.36% before the
  // refinement within the count, 3.79% before the tip splits), the elephant 1.59 -> 0.92% and
  // mech-holes-shark 1.20 -> 0.92% with them; mech-holes-shark was 7.1% before its lens-shaped
  // patch got a width target, knot1 2.16 -> 1.40% with tip snapping.
  EXPECT_LT(q.hausdorff, 0.02);
  // Nothing is said of folds (none is left).
  expect_folds_said(said, quads, input);
  // Every output vertex lies on the input surface (placed through provenance), as the
  // preparation triangulated it (non-planar polygons have no other surface).
  std::vector<std::array<Vec3, 3>> tris;
  Box3 box;
  for (const PreparedComponent& c : prep.components)
    for (const Tri& t : c.mesh.faces()) {
      std::array<Vec3, 3> w;
      for (int k = 0; k < 3; ++k) w[k] = prep.normalization.invert(c.mesh.position(t[k]));
      tris.push_back(w);
    }
  for (const Vec3& p : input.mesh.positions) box.add(p);
  const AabbTree tree(tris);
  double worst = 0;
  for (const Vec3& p : quads.positions) worst = std::max(worst, tree.closest(p).distance);
  EXPECT_LT(worst, 1e-9 * box.diagonal());

  const auto dir = std::filesystem::temp_directory_path() /
                   ("isoquad_report_" + std::to_string(::getpid()) + "_" + GetParam());
  ReportOptions ro;
  ro.width = 360;
  write_report(dir, input.mesh, run, ro);
  const nlohmann::json report = test::expect_valid_report(dir);
  EXPECT_EQ(report.at("quality"), nlohmann::json(q));  // what `isoquad quality` would print
  std::filesystem::remove_all(dir);
  RecordProperty("quads", int(quads.num_faces()));
  RecordProperty("sj_nonpositive", int(q.sj_nonpositive));
  RecordProperty("sj_surface_nonpositive", int(q.sj_surface_nonpositive));
  RecordProperty("hausdorff_permille", int(1000 * q.hausdorff));
}

// At the default size (one quad per 8 input triangles, 1,000 to 20,000): the same validity, and
// bounds that hold today (no folded quad: the anchor's went with the flips of its needles, the
// cow's 2 with the tip rounds; knot1 folded 25 before the second choice of corners, 2% of its
// quads before the untangler descended one energy).
TEST_P(CorpusRemesh, DefaultSizeIsValid) {
  ISOQUAD_CORPUS_MESH(path, GetParam());
  const ReadResult input = read_mesh(path);
  const RemeshRun run = remesh_run(input.mesh, RemeshOptions{}, input.unshared_vertices);
  const PolyMesh& quads = run.result.quads;
  for (const ComponentRun& r : run.runs) {
    EXPECT_LE(r.untangle_report.folded_after, r.untangle_report.folded_before);
    EXPECT_LE(r.snap_report.farthest_after, r.snap_report.farthest_before);
  }
  expect_lengths_near_targets(run);
  const QualityReport q = measure_quality(quads, &input.mesh);
  test::expect_valid_quad_mesh(q);
  EXPECT_GE(quads.num_faces(), 900u);
  expect_tip_split_kept_only_if_better(run, q, 0);
  expect_patch_rounds_kept_only_if_better(run, 0);
  EXPECT_GT(shortest_edge(quads), 1e-6);
  EXPECT_EQ(q.sj_surface_nonpositive, 0u);
  expect_valid_against_own_normal(q, GetParam(), 0);
  // Within 1%. The cow is at 0.999%, with OpenBLAS's Cooperlake and SkylakeX kernels alike
  // (README, Threads: other kernels round otherwise), where its first run's two folded quads go
  // with the misfit split and the tips and the refinement then close in; it was 2.32% before
  // (2.30% with a fold with the Cooperlake kernels). The elephant was 2.20% before the patch
  // rounds (3.0% before tip snapping, 3.8% before the raised request); mech-holes-shark 7.3%
  // before the width targets, 2.52% before the tip splits, 1.19% before the patch rounds, 0.99%
  // with twice its patches.
  EXPECT_LT(q.hausdorff, 0.01);
  // The Hausdorff distance is no lower than the farthest of 136 lattice points on each of the
  // quads' triangles (the measure's bound is within 0.1%; at the default size the quads are
  // coarse next to their distance, where a budget of points cut short the bisection of the
  // hand's quads at 0.987% of the diagonal for 1.022%).
  std::vector<std::array<Vec3, 3>> reference_triangles, quad_triangles;
  Box3 box;
  for (const Vec3& p : input.mesh.positions) box.add(p);
  for (std::size_t f = 0; f < input.mesh.num_faces(); ++f) {
    const auto v = input.mesh.face(f);
    for (std::size_t i = 1; i + 1 < v.size(); ++i)
      reference_triangles.push_back(
          {input.mesh.positions[v[0]], input.mesh.positions[v[i]], input.mesh.positions[v[i + 1]]});
  }
  const AabbTree reference(reference_triangles);
  double lattice = 0;
  constexpr int kSteps = 15;
  for (std::size_t f = 0; f < quads.num_faces(); ++f) {
    const auto v = quads.face(f);
    for (std::size_t i = 1; i + 1 < v.size(); ++i) {
      const Vec3 a = quads.positions[v[0]], b = quads.positions[v[i]],
                 c = quads.positions[v[i + 1]];
      for (int j = 0; j <= kSteps; ++j)
        for (int k = 0; j + k <= kSteps; ++k)
          lattice = std::max(
              lattice,
              reference.closest(a + (double(j) / kSteps) * (b - a) + (double(k) / kSteps) * (c - a))
                  .distance);
    }
  }
  EXPECT_GE(q.hausdorff, (1 - kMaxDistanceRelativeError) * lattice / box.diagonal());
  RecordProperty("quads", int(quads.num_faces()));
  RecordProperty("sj_surface_nonpositive", int(q.sj_surface_nonpositive));
  RecordProperty("hausdorff_permille", int(1000 * q.hausdorff));
}

INSTANTIATE_TEST_SUITE_P(Corpus, CorpusRemesh, testing::ValuesIn(test::kCorpusMeshes),
                         [](const testing::TestParamInfo<const char*>& info) {
                           return test::corpus_case_name(info.param, 0);
                         });

// The last-resort repair forced on (--split-patches): every patch four-sided, and the whole
// method still gives a valid pure quad mesh of the input's topology. On fandisk (closed, with
// creases), nefertiti (open), eight (genus 2) and mech-holes-shark (four boundary loops); all 19
// corpus meshes pass, these four keep CI short.
TEST(CorpusQuadSplit, FourSidedPatchesGiveAValidMesh) {
  for (const char* file : {"fandisk.off", "nefertiti.off", "eight.off", "mech-holes-shark.off"}) {
    SCOPED_TRACE(file);
    ISOQUAD_CORPUS_MESH(path, file);
    const ReadResult input = read_mesh(path);
    RemeshOptions o;
    o.quads = 1500;
    o.split_patches = true;
    const RemeshRun run = remesh_run(input.mesh, o, input.unshared_vertices);
    int64_t layout_quads = 0, repaired = 0;
    for (const ComponentRun& r : run.runs) {
      ASSERT_TRUE(r.quad_split.has_value());
      EXPECT_GT(r.quad_split->patches_after, r.quad_split->patches_before);
      for (const MetaFace& f : r.seg.meta.faces) EXPECT_EQ(f.cycle.size(), 4u);
      EXPECT_EQ(r.extract_report.multiply_covered, 0u);
      layout_quads += r.layout.quads();
      repaired += int64_t(r.extract_report.quads) - r.layout.quads();  // cut finer where far
      repaired += 4 * int64_t(r.untangle_report.split) - r.untangle_report.collapsed -
                  r.untangle_report.doublets;
    }
    const QualityReport q = measure_quality(run.result.quads, &input.mesh);
    test::expect_valid_quad_mesh(q);
    expect_valid_against_own_normal(q, std::string(file) + " --split-patches", 1500);
    // The layout lands near the request; the repairs then add (splits at 180-degree crease
    // corners, of which four-sided patches have many: fandisk 29, +116 quads) or remove quads.
    EXPECT_NEAR(double(layout_quads), 1500.0, 150.0);
    EXPECT_EQ(int64_t(run.result.quads.num_faces()), layout_quads + repaired);
  }
}

// The cactus at the default size: its quads cut an arm's end off, 1% of the diagonal and more
// than 0.3 edge lengths; with such points patch corners the run again is kept, the arm's end is
// covered (the quads come within a third of the distance there) and the distance drops (1.03% ->
// 0.87%, the rest elsewhere). Without the split there is one run.
TEST(CorpusTipSplit, CutOffArmEndBecomesACorner) {
  ISOQUAD_CORPUS_MESH(path, "cactus.off");
  const ReadResult input = read_mesh(path);
  const Without w = remesh_without(input, [](RemeshOptions& o) {
    o.tip_split = false;
    o.refine = false;
    o.patch_rounds = false;
  });
  const RemeshRun& once = w.run;
  EXPECT_TRUE(once.runs.at(0).tips.empty());
  const double before = w.quality.hausdorff;
  const RemeshRun run = remesh_run(input.mesh, RemeshOptions{}, input.unshared_vertices);
  const ComponentRun& r = run.runs.at(0);
  ASSERT_FALSE(r.tips.empty());
  ASSERT_GE(r.tip_round_kept, 1u);
  EXPECT_GE(r.seg.tip_split.split + r.seg.tip_split.boundary.size(), 1u);
  for (const uint32_t t : r.tips) EXPECT_NE(r.seg.meta.vertex_meta_vertex[t], kInvalid);
  // the first run is the run without
  EXPECT_NEAR(r.tip_rounds.at(0).result.distance, before, 0.1 * before);
  const QualityReport q = measure_quality(run.result.quads, &input.mesh);
  EXPECT_TRUE(q.pure_quad);
  EXPECT_TRUE(q.same_topology);
  EXPECT_EQ(q.sj_surface_nonpositive, 0u);
  expect_valid_against_own_normal(q, "cactus.off", 0);
  EXPECT_LT(q.hausdorff, before);
  EXPECT_LT(q.hausdorff, 0.01);
  ASSERT_TRUE(w.quality.hausdorff_on_input);  // the arm's end, a point the quads miss
  std::vector<std::array<Vec3, 3>> tris;
  const PolyMesh& quads = run.result.quads;
  for (std::size_t f = 0; f < quads.num_faces(); ++f) {
    const auto v = quads.face(f);
    tris.push_back({quads.positions[v[0]], quads.positions[v[1]], quads.positions[v[2]]});
    tris.push_back({quads.positions[v[0]], quads.positions[v[2]], quads.positions[v[3]]});
  }
  Box3 box;
  for (const Vec3& p : input.mesh.positions) box.add(p);
  EXPECT_LT(AabbTree(tris).closest(w.quality.hausdorff_at).distance, box.diagonal() * before / 3);
}

// The anchor at the default size: after its run (no tip run kept), its quads are 1.27% of the
// diagonal from the surface. The quads around the lattice points nearest to the far points are
// cut at thirds in the same map, and the result is within 1%, with a few more quads and
// irregular vertices where the finer quads end (2,161 -> 2,171 quads and 0.78% in one round when
// this was written). Without the refinement the first quads stay. (The eight served here until
// the untangler took the quads' own normals too: its first run now comes within 1% by the patch
// rounds, with no refinement kept.)
TEST(CorpusRefine, FarQuadsCutFinerReachTheTarget) {
  ISOQUAD_CORPUS_MESH(path, "anchor.off");
  const ReadResult input = read_mesh(path);
  const Without w = remesh_without(input, [](RemeshOptions& o) {
    o.refine = false;
    o.patch_rounds = false;
  });
  const RemeshRun& once = w.run;
  EXPECT_TRUE(once.runs.at(0).refine_rounds.empty());
  const QualityReport& before = w.quality;
  ASSERT_GT(before.hausdorff, kTipTarget);
  const RemeshRun run = remesh_run(input.mesh, RemeshOptions{}, input.unshared_vertices);
  const ComponentRun& r = run.runs.at(0);
  ASSERT_GE(r.refine_round_kept, 1u);
  // Its first figures are the unrefined run's.
  EXPECT_EQ(r.refine_rounds.at(0).result.quads, once.result.quads.num_faces());
  const QualityReport q = expect_valid_output(run.result.quads, input, "anchor.off", 0);
  EXPECT_LT(q.hausdorff, kTipTarget);
  EXPECT_GT(run.result.quads.num_faces(), once.result.quads.num_faces());
  EXPECT_LT(double(run.result.quads.num_faces()), 1.2 * double(once.result.quads.num_faces()));
  EXPECT_GT(q.irregular, before.irregular);
  EXPECT_LT(q.irregular, 4 * before.irregular);
  // Every vertex on the surface (the refined points are placed by the map like lattice points).
  const AabbTree tree(face_triangles(run.prep.components[0].mesh));
  for (const ComponentRun& c : run.runs)
    for (const Vec3& p : c.quads.positions) EXPECT_LT(tree.closest(p).distance, 1e-9);
}

// The anchor at 1,500 quads with the repairs after untangling turned off (fold rounds, corner
// tries, misfit split, tips, refinement, patch rounds) keeps quads folded against the surface (2
// when this was written, at a fluke's edge): the run says so on the progress channel, with the
// count and the centre of the most folded quad, and the JSON has the same count. The corpus test
// at 1,500 quads sees only the case without folds.
TEST(CorpusFoldWarning, FoldsLeftAreSaidWithWhere) {
  ISOQUAD_CORPUS_MESH(path, "anchor.off");
  const ReadResult input = read_mesh(path);
  RemeshOptions o;
  o.quads = 1500;
  o.fold_rounds = 0;
  o.misfit_split = false;
  o.tip_split = false;
  o.refine = false;
  o.patch_rounds = false;
  std::vector<std::string> said;
  const RemeshRun run = remesh_run(input.mesh, o, input.unshared_vertices,
                                   [&](const std::string& s) { said.push_back(s); });
  const QualityReport q = measure_quality(run.result.quads, &input.mesh);
  EXPECT_TRUE(q.pure_quad);
  EXPECT_TRUE(q.same_topology);
  const uint32_t folded = folded_quads(run.result.quads, input);
  ASSERT_GT(folded, 0u) << "no fold left: the test needs another case";
  EXPECT_EQ(run.runs.at(0).untangle_report.nonpositive, folded);
  const auto json = nlohmann::json::parse(run.result.report)["components"][0]["untangle"];
  EXPECT_EQ(json["nonpositive"].get<uint32_t>(), folded);
  expect_folds_said(said, run.result.quads, input);
}

// The elephant at the default size: after its tip runs and the refinement its quads are still
// 1.61% of the diagonal from the surface (2.20% with OpenBLAS's SkylakeX kernels; 62 patches
// crowd the map at its trunk and ears). The patch rounds run it again with 1.5 and 2 times the
// patches; the first within 1% with no more folded quads is kept (88 patches and 0.83%, or 112
// and 0.90%, when this was written). mech-holes-shark served here until the refinement, cutting
// around points instead of whole quads, took it within 1% alone.
TEST(CorpusPatchRounds, MorePatchesReachTheTarget) {
  ISOQUAD_CORPUS_MESH(path, "elephant.off");
  const ReadResult input = read_mesh(path);
  const Without w = remesh_without(input, [](RemeshOptions& o) { o.patch_rounds = false; });
  const RemeshRun& once = w.run;
  EXPECT_TRUE(once.runs.at(0).patch_rounds.empty());
  const QualityReport& before = w.quality;
  ASSERT_GT(before.hausdorff, kTipTarget);
  std::string progress;
  const RemeshRun run = remesh_run(input.mesh, RemeshOptions{}, input.unshared_vertices,
                                   [&](const std::string& line) { progress += line + "\n"; });
  const ComponentRun& r = run.runs.at(0);
  const auto& rounds = r.patch_rounds;
  ASSERT_GE(r.patch_round_kept, 1u);
  // The JSON and the progress say the same.
  const auto tried = nlohmann::json::parse(run.result.report)["components"][0]["patch_rounds"];
  EXPECT_EQ(tried["kept"].get<std::size_t>(), r.patch_round_kept);
  ASSERT_EQ(tried["tried"].size(), rounds.size());
  for (std::size_t k = 0; k < rounds.size(); ++k) {
    EXPECT_EQ(tried["tried"][k]["patches"].get<uint32_t>(), rounds[k].patches);
    EXPECT_EQ(tried["tried"][k]["quads"].get<uint64_t>(), rounds[k].result.quads);
  }
  EXPECT_NE(progress.find("more patches: " + std::to_string(rounds[0].patches) + " patches"),
            std::string::npos)
      << progress;
  // The first round is the run without: its VSA patches and quads.
  EXPECT_EQ(rounds.at(0).patches, once.runs[0].seg.vsa_patches);
  EXPECT_EQ(rounds[0].result.quads, once.result.quads.num_faces());
  EXPECT_NEAR(rounds[0].result.distance, before.hausdorff, 0.02 * before.hausdorff);
  // More patches each round; the kept one is the last, within the target, with no more folds.
  for (std::size_t k = 1; k < rounds.size(); ++k)
    EXPECT_GT(rounds[k].patches, rounds[k - 1].patches);
  EXPECT_EQ(r.patch_round_kept + 1, rounds.size());
  EXPECT_EQ(r.seg.vsa_patches, rounds.back().patches);
  EXPECT_LE(rounds.back().result.distance, kTipTarget);
  EXPECT_LE(rounds.back().result.folded, rounds[0].result.folded);
  EXPECT_EQ(rounds.back().result.quads, run.result.quads.num_faces());
  const QualityReport q = expect_valid_output(run.result.quads, input, "elephant.off", 0);
  EXPECT_LT(q.hausdorff, kTipTarget);
  EXPECT_LT(q.hausdorff, before.hausdorff);
  const AabbTree tree(face_triangles(run.prep.components[0].mesh));
  for (const Vec3& p : r.quads.positions) EXPECT_LT(tree.closest(p).distance, 1e-9);
  // With a patch count asked for, there are no rounds.
  RemeshOptions fixed;
  fixed.patches = once.runs[0].seg.vsa_patches;
  EXPECT_TRUE(remesh_run(input.mesh, fixed, input.unshared_vertices).runs[0].patch_rounds.empty());
}

// The hand at 700 quads: its run without tips has 703 quads, 3.04% from the surface; with seven
// tips as patch corners it came to 831 quads (1.61%), past the count asked for. Tip runs past 1.1
// times the count are not kept (708 quads with one tip, refined to 758 and 1.75%, when this was
// written; at 800 quads, where this test ran before, no tip run now passes the count).
TEST(CorpusTipSplit, TipRunsKeepTheCountAskedFor) {
  ISOQUAD_CORPUS_MESH(path, "hand.off");
  const ReadResult input = read_mesh(path);
  RemeshOptions o;
  o.quads = 700;
  const RemeshRun run = remesh_run(input.mesh, o, input.unshared_vertices);
  const ComponentRun& r = run.runs.at(0);
  const auto& rounds = r.tip_rounds;
  ASSERT_GE(rounds.size(), 2u);
  // Some tip run went past the count (this is what the test is about)...
  EXPECT_TRUE(std::any_of(rounds.begin(), rounds.end(), [&](const auto& t) {
    return double(t.result.quads) > kCountSlack * 700;
  }));
  // ...and the kept one is within it. The JSON lists each run's quads.
  EXPECT_LE(double(rounds.at(r.tip_round_kept).result.quads), kCountSlack * 700);
  const auto tried = nlohmann::json::parse(run.result.report)["components"][0]["tip_split"];
  ASSERT_EQ(tried["tried"].size(), rounds.size());
  for (std::size_t k = 0; k < rounds.size(); ++k)
    EXPECT_EQ(tried["tried"][k]["quads"].get<uint64_t>(), rounds[k].result.quads);
  const PolyMesh& quads = run.result.quads;
  EXPECT_GE(double(quads.num_faces()), 0.9 * 700);
  EXPECT_LE(double(quads.num_faces()), kCountSlack * 700);
  const QualityReport q = expect_valid_output(quads, input, "hand.off", 700);
  EXPECT_LT(q.hausdorff, rounds[0].result.distance);
}

// The mushroom at 3,000 quads: one quad stays folded through the fold rounds, the collapses and
// the corner tries, in a fan of slivers where one patch's facing sides are 9.5 times apart. The
// last try cuts the VSA regions of such misfit patches in two and runs the stages again; it is
// kept only with fewer folded quads (here 1 -> 0). The map's floating point follows the
// machine's BLAS kernels, so where the mushroom does not fold on some machine there is nothing
// to try and the test says so.
TEST(CorpusMisfitSplit, KeptOnlyWithFewerFolds) {
  ISOQUAD_CORPUS_MESH(path, "mushroom.off");
  const ReadResult input = read_mesh(path);
  RemeshOptions o;
  o.quads = 3000;
  std::string progress;
  const RemeshRun run = remesh_run(input.mesh, o, input.unshared_vertices,
                                   [&](const std::string& line) { progress += line + "\n"; });
  const ComponentRun& r = run.runs.at(0);
  const ComponentRun::MisfitSplit& split = r.misfit_split;
  const PolyMesh& quads = run.result.quads;
  const QualityReport q = measure_quality(quads, &input.mesh);
  EXPECT_TRUE(q.pure_quad);
  EXPECT_TRUE(q.edge_manifold);
  EXPECT_TRUE(q.vertex_manifold);
  EXPECT_TRUE(q.same_topology);
  EXPECT_GE(double(quads.num_faces()), 0.9 * 3000);
  EXPECT_LE(double(quads.num_faces()), 1.1 * 3000);
  EXPECT_LT(q.hausdorff, kTipTarget);
  expect_valid_against_own_normal(q, "mushroom.off", 3000);
  if (split.regions == 0) GTEST_SKIP() << "no quad folded after the corner tries: nothing to cut";
  EXPECT_GE(split.folded_before, 1u);
  if (split.kept) {
    EXPECT_LE(split.folded_after, split.folded_before);
  }
  // The output is the run kept.
  EXPECT_EQ(r.untangle_report.nonpositive, split.kept ? split.folded_after : split.folded_before);
  EXPECT_EQ(folded_quads(quads, input), r.untangle_report.nonpositive);
  // The JSON and the progress say the same.
  const auto json = nlohmann::json::parse(run.result.report)["components"][0]["misfit_split"];
  EXPECT_EQ(json["regions"].get<uint32_t>(), split.regions);
  EXPECT_EQ(json["folded_before"].get<uint32_t>(), split.folded_before);
  EXPECT_EQ(json["folded_after"].get<uint32_t>(), split.folded_after);
  EXPECT_EQ(json["kept"].get<bool>(), split.kept);
  EXPECT_NE(progress.find(fmt::format("misfit patches cut in two for folds: {} regions, {} -> {} "
                                      "folded{}",
                                      split.regions, split.folded_before, split.folded_after,
                                      split.kept ? " (kept)" : "")),
            std::string::npos)
      << progress;
}

// Subdivision stops before a level would take the surface past 250,000 faces: rotor (1,200
// faces) at 10,000 quads wants 80,000 triangles and gets 3 levels, 76,800 (a fourth level made
// 307,200, and the run took minutes instead of seconds).
TEST(CorpusSubdivision, StopsBeforeTheFaceCap) {
  ISOQUAD_CORPUS_MESH(path, "rotor.off");
  const PreparedMesh prep = prepare(read_mesh(path).mesh);
  ASSERT_EQ(prep.components.size(), 1u);
  const PreparedComponent& comp = prep.components[0];
  EdgeData<char> feature;
  uint32_t levels = 0;
  const double h = edge_length_for_quads(comp.mesh, 10000);
  const RefinedMesh r = subdivide_coarse(comp.mesh, comp.feature, h, 8, feature, levels);
  EXPECT_EQ(levels, 3u);
  EXPECT_EQ(r.mesh.num_faces(), 64 * comp.mesh.num_faces());
  EXPECT_LE(r.mesh.num_faces(), 250000u);
}

// Zero-area triangles on a real mesh: fandisk (creases, CAD) with one vertex moved onto a
// neighbour (two zero-area triangles, E551 before) and another onto the middle of its opposite
// edge (a cap). Preparation collapses the one edge and flips the other (W116), and the remesh
// is valid, of the input's topology, near the count asked for.
TEST(CorpusZeroArea, VertexOnANeighbourAndOnAnEdgeAreRepairedAndRemeshed) {
  ISOQUAD_CORPUS_MESH(path, "fandisk.off");
  ReadResult input = read_mesh(path);
  PolyMesh& m = input.mesh;
  const auto a = m.face(100), b = m.face(3000);
  ASSERT_EQ(std::count_if(a.begin(), a.end(),
                          [&](uint32_t v) { return std::find(b.begin(), b.end(), v) != b.end(); }),
            0);
  m.positions[a[0]] = m.positions[a[1]];
  m.positions[b[2]] = 0.5 * (m.positions[b[0]] + m.positions[b[1]]);
  RemeshOptions o;
  o.quads = 1500;
  const RemeshRun run = remesh_run(m, o, input.unshared_vertices, [](const std::string&) {});
  const ComponentReport& c = run.prep.report.components.at(0);
  EXPECT_EQ(c.zero_area_collapsed, 1u);
  EXPECT_EQ(c.zero_area_flipped, 1u);
  EXPECT_EQ(c.zero_area_faces, 0u);
  uint32_t said = 0;
  for (const InputIssue& i : run.prep.report.issues)
    if (i.code == "W116") said += i.count;
  EXPECT_EQ(said, 2u);
  const QualityReport q = measure_quality(run.result.quads, &input.mesh);
  EXPECT_TRUE(q.pure_quad && q.edge_manifold && q.vertex_manifold && q.oriented);
  EXPECT_TRUE(q.same_topology);
  EXPECT_EQ(q.sj_invalid, 0u);
  EXPECT_EQ(q.sj_surface_nonpositive, 0u);
  EXPECT_NEAR(double(run.result.quads.num_faces()), 1500.0, 150.0);
  for (const ComponentRun& r : run.runs) EXPECT_FALSE(r.triangle_split);
}
