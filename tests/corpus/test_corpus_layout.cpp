// Layout on every corpus mesh at K = auto, 8 and 30 and at 500, 1,500 and 5,000 quads: a layout
// is always found (repairs included), every constraint holds exactly, every check passes, and
// the quad count is close to the request where the patches allow it.
#include <gtest/gtest.h>

#include "corpus.hpp"
#include "io/read_mesh.hpp"
#include "layout_checks.hpp"
#include "pipeline/sizing.hpp"
#include "prep/prepare.hpp"
#include "seg/segment.hpp"

using namespace isoquad;

namespace {

using Param = std::tuple<const char*, uint32_t>;
class CorpusLayout : public testing::TestWithParam<Param> {};

}  // namespace

TEST_P(CorpusLayout, FeasibleExactAndSized) {
  const auto [file, k] = GetParam();
  ISOQUAD_CORPUS_MESH(path, file);
  const PreparedMesh p = prepare(read_mesh(path).mesh);
  const PreparedComponent& c = p.components.at(0);
  for (const double quads : {500.0, 1500.0, 5000.0}) {
    SCOPED_TRACE(testing::Message() << quads << " quads");
    const SegmentOptions so = SegmentOptions::sized(edge_length_for_quads(c.mesh, quads), k);
    SegmentResult seg = segment(c.mesh, c.feature, so);
    LayoutOptions lo;
    lo.quads = quads;
    LayoutReport report;
    const MetaMesh meta_before = seg.meta;
    const Layout l = solve_layout(seg.refined.mesh, seg.labels, seg.feature, seg.meta, lo, report);
    test::expect_valid_layout(seg.meta, l);
    if (quads == 1500) {  // same input, same layout (no dependence on solver timing)
      MetaMesh again_meta = meta_before;
      LayoutReport again_report;
      const Layout again =
          solve_layout(seg.refined.mesh, seg.labels, seg.feature, again_meta, lo, again_report);
      EXPECT_EQ(again.length, l.length);
      EXPECT_EQ(again.quarter_turns, l.quarter_turns);
    }
    EXPECT_TRUE(report.length_optimal);
    for (uint32_t v = 0; v < l.quarter_turns.size(); ++v)
      EXPECT_GE(l.quarter_turns[v], seg.meta.vertices[v].on_boundary ? 1 : 3)
          << "degenerate valence";
    // Never far too few quads; at 5,000 (where every patch holds many) within 10%. Smaller
    // requests can be below what the patches' integer constraints allow.
    EXPECT_GE(double(l.quads()), 0.9 * quads);
    if (quads >= 5000) {
      EXPECT_LE(double(l.quads()), 1.1 * quads);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Corpus, CorpusLayout,
                         testing::Combine(testing::ValuesIn(test::kCorpusMeshes),
                                          testing::Values(0u, 8u, 30u)),
                         [](const testing::TestParamInfo<Param>& info) {
                           return test::corpus_case_name(std::get<0>(info.param),
                                                         std::get<1>(info.param));
                         });

// The corner refinement against the relaxed length program keeps layouts valid and lowers the
// length objective where the per-patch corner choice fights the side equations.
TEST(CorpusLayoutImprove, CornersRefinedAgainstTheLengths) {
  for (const char* file : {"fandisk.off", "cow.off"}) {
    SCOPED_TRACE(file);
    ISOQUAD_CORPUS_MESH(path, file);
    const PreparedMesh p = prepare(read_mesh(path).mesh);
    const PreparedComponent& c = p.components.at(0);
    const SegmentOptions so = SegmentOptions::sized(edge_length_for_quads(c.mesh, 1500));
    const SegmentResult seg = segment(c.mesh, c.feature, so);
    double objective[2];
    for (const bool improve : {false, true}) {
      LayoutOptions lo;
      lo.quads = 1500;
      lo.improve_corners = improve;
      LayoutReport report;
      MetaMesh meta = seg.meta;
      const Layout l = solve_layout(seg.refined.mesh, seg.labels, seg.feature, meta, lo, report);
      test::expect_valid_layout(meta, l);
      EXPECT_TRUE(report.length_optimal);
      objective[improve] = l.objective;
    }
    EXPECT_LT(objective[1], 0.8 * objective[0]);
  }
}

// Pruning the refinement's trials by their Lagrangian bound is exact: the same corners, lengths
// and objective with it and without it, on meshes where the refinement changes many patches.
TEST(CorpusLayoutImprove, PrunedTrialsGiveTheSameLayout) {
  for (const char* file : {"fandisk.off", "cow.off", "elephant.off"}) {
    SCOPED_TRACE(file);
    ISOQUAD_CORPUS_MESH(path, file);
    const PreparedMesh p = prepare(read_mesh(path).mesh);
    const PreparedComponent& c = p.components.at(0);
    const SegmentResult seg =
        segment(c.mesh, c.feature, SegmentOptions::sized(edge_length_for_quads(c.mesh, 1500)));
    Layout l[2];
    LayoutReport report[2];
    for (const bool prune : {false, true}) {
      LayoutOptions lo;
      lo.quads = 1500;
      lo.prune_corner_trials = prune;
      MetaMesh meta = seg.meta;
      l[prune] = solve_layout(seg.refined.mesh, seg.labels, seg.feature, meta, lo, report[prune]);
    }
    EXPECT_EQ(l[1].quarter_turns, l[0].quarter_turns);
    EXPECT_EQ(l[1].length, l[0].length);
    EXPECT_NEAR(l[1].objective, l[0].objective, 1e-9);
    EXPECT_EQ(report[1].repairs, report[0].repairs);  // "corners of N patches improved"
  }
}

// Where the best corners force meta-edges to zero, re-choosing the corners of the patches
// along them one at a time is usually enough, and much cheaper than the feasibility-aware ILP.
TEST(LayoutRepair, GreedyCornerRepairOnTheSampleFandisk) {
  const PreparedMesh p = prepare(read_mesh(test::data_dir() / "fandisk.off").mesh);
  const PreparedComponent& c = p.components.at(0);
  const SegmentOptions so = SegmentOptions::sized(edge_length_for_quads(c.mesh, 500));
  SegmentResult seg = segment(c.mesh, c.feature, so);
  LayoutOptions lo;
  lo.quads = 500;
  lo.improve_corners = false;  // its own repair line would follow
  LayoutReport report;
  const Layout l = solve_layout(seg.refined.mesh, seg.labels, seg.feature, seg.meta, lo, report);
  test::expect_valid_layout(seg.meta, l);
  ASSERT_EQ(report.repairs.size(), 2u);
  EXPECT_NE(report.repairs[0].find("force"), std::string::npos) << report.repairs[0];
  EXPECT_NE(report.repairs[1].find("one by one"), std::string::npos) << report.repairs[1];
  EXPECT_EQ(report.corner_rounds, 1u);  // the ILP repair did not run
}
