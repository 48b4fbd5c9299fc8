// Parametrization on every corpus mesh at K = auto, 8 and 30 (1,500 quads): the map is
// certified injective, seam vertices agree across their transitions, meta-vertices sit on
// their lattice points; and the paper's Figure 2 effect: without stiffening, maps flip.
#include <gtest/gtest.h>

#include "corpus.hpp"
#include "io/read_mesh.hpp"
#include "isoquad/error.hpp"
#include "param_checks.hpp"
#include "pipeline/pipeline.hpp"
#include "prep/prepare.hpp"

using namespace isoquad;

namespace {

using Case = std::tuple<const char*, uint32_t>;
class CorpusParam : public testing::TestWithParam<Case> {};

}  // namespace

TEST_P(CorpusParam, CertifiedAndSeamless) {
  const auto [file, k] = GetParam();
  ISOQUAD_CORPUS_MESH(path, file);
  const PreparedMesh p = prepare(read_mesh(path).mesh);
  PipelineOptions o;
  o.last = Stage::param;
  o.patches = k;
  o.quads = 1500;
  const ComponentRun run = run_component(p, 0, o);
  const TriMesh& mesh = run.seg.refined.mesh;
  test::expect_certified(mesh, run.seg.labels, run.seg.meta, run.layout, run.param);
  const ParamReport& r = run.param_report;
  EXPECT_FALSE(r.fell_back_to_locked);
  EXPECT_EQ(r.symbolic, 2u);  // the locked scalar system and the coupled one, once each
  EXPECT_EQ(r.factorizations, r.iterations + 1);  // the locked map, then one per round
  EXPECT_LE(r.factorizations, 8u);
  EXPECT_LT(r.max_residual, 1e-10);
}

INSTANTIATE_TEST_SUITE_P(Corpus, CorpusParam,
                         testing::Combine(testing::ValuesIn(test::kCorpusMeshes),
                                          testing::Values(0u, 8u, 30u)),
                         [](const testing::TestParamInfo<Case>& info) {
                           return test::corpus_case_name(std::get<0>(info.param),
                                                         std::get<1>(info.param));
                         });

// Paper Figure 2: with every weight 1 and no stiffening the map of a real mesh has flipped
// triangles; the locked map of the same layout has none.
TEST(CorpusParamFigure2, UnitWeightsFlipLockedDoesNot) {
  ISOQUAD_CORPUS_MESH(path, "elephant.off");
  const PreparedMesh p = prepare(read_mesh(path).mesh);
  PipelineOptions o;
  o.last = Stage::param;
  o.quads = 1500;
  o.param.relax = RelaxMode::none;
  const ComponentRun run = run_component(p, 0, o);
  EXPECT_GT(run.param_report.flipped_unstiffened, 0u);
  EXPECT_GT(run.param.certificate.flipped, 0u);
  const Certificate locked =
      certify(run.seg.refined.mesh, run.seg.labels, run.seg.meta, run.layout, run.param.locked);
  EXPECT_TRUE(locked.ok());
}
