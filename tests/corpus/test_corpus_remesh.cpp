// The whole method on every corpus mesh at 1,500 quads: the output is pure quad, edge- and
// vertex-manifold, consistently oriented, and has the input's components, boundary loops and
// Euler characteristic; its quad count is what the layout promised.
#include <gtest/gtest.h>

#include "corpus.hpp"
#include "io/read_mesh.hpp"
#include "metrics/aabb_tree.hpp"
#include "metrics/quality.hpp"
#include "pipeline/pipeline.hpp"
#include "prep/prepare.hpp"

using namespace isoquad;

namespace {
class CorpusRemesh : public testing::TestWithParam<const char*> {};
}  // namespace

TEST_P(CorpusRemesh, ValidPureQuadMeshOfTheSameTopology) {
  ISOQUAD_CORPUS_MESH(path, GetParam());
  const ReadResult input = read_mesh(path);
  const PreparedMesh prep = prepare(input.mesh);
  PipelineOptions o;
  o.quads = 1500;
  const std::vector<ComponentRun> runs = run_pipeline(prep, o);
  const PolyMesh quads = merge_quads(prep, runs);
  int64_t promised = 0;
  for (const ComponentRun& r : runs) promised += r.layout.quads();
  EXPECT_EQ(int64_t(quads.num_faces()), promised);
  QualityOptions qo;
  qo.samples = 5000;
  const QualityReport q = measure_quality(quads, &input.mesh, qo);
  EXPECT_TRUE(q.pure_quad);
  EXPECT_TRUE(q.edge_manifold);
  EXPECT_TRUE(q.vertex_manifold);
  EXPECT_TRUE(q.oriented);
  EXPECT_TRUE(q.same_topology) << "chi " << q.topology.euler << " vs "
                               << q.reference_topology->euler;
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
  RecordProperty("quads", int(quads.num_faces()));
  RecordProperty("sj_nonpositive", int(q.sj_nonpositive));
  RecordProperty("hausdorff_permille", int(1000 * q.hausdorff));
}

INSTANTIATE_TEST_SUITE_P(Corpus, CorpusRemesh, testing::ValuesIn(test::kCorpusMeshes),
                         [](const testing::TestParamInfo<const char*>& info) {
                           return test::corpus_case_name(info.param, 0);
                         });
