// Segmentation on every corpus mesh at K = auto, 8 and 30: disks, no pinches, at least 4
// meta-vertices per patch, a consistent meta-mesh with the mesh's Euler characteristic, seams
// never lengthened, and the same labels on a second run.
#include <gtest/gtest.h>

#include "corpus.hpp"
#include "io/read_mesh.hpp"
#include "pipeline/sizing.hpp"
#include "prep/prepare.hpp"
#include "seg_checks.hpp"

using namespace isoquad;

namespace {

using Param = std::tuple<const char*, uint32_t>;
class CorpusSegment : public testing::TestWithParam<Param> {};

}  // namespace

TEST_P(CorpusSegment, PatchesAreDisksAndMetaMeshIsConsistent) {
  const auto [file, k] = GetParam();
  ISOQUAD_CORPUS_MESH(path, file);
  const PreparedMesh p = prepare(read_mesh(path).mesh);
  const PreparedComponent& c = p.components.at(0);
  const SegmentOptions o = SegmentOptions::sized(
      edge_length_for_quads(c.mesh, default_quad_count(c.mesh.num_faces())), k);
  const SegmentResult r = segment(c.mesh, c.feature, o);
  test::expect_valid_segmentation(c.mesh, r);
  if (k > 0) {
    // Regions below the size floor may merge, but never most of them.
    EXPECT_GE(4 * r.num_patches, 3 * k) << "far fewer patches than asked";
  }
  if (c.mesh.num_faces() <= 15000) {
    const SegmentResult again = segment(c.mesh, c.feature, o);
    EXPECT_EQ(again.labels.values(), r.labels.values());
  }
}

INSTANTIATE_TEST_SUITE_P(Corpus, CorpusSegment,
                         testing::Combine(testing::ValuesIn(test::kCorpusMeshes),
                                          testing::Values(0u, 8u, 30u)),
                         [](const testing::TestParamInfo<Param>& info) {
                           return test::corpus_case_name(std::get<0>(info.param),
                                                         std::get<1>(info.param));
                         });
