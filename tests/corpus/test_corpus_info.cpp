// Every corpus mesh is read and prepared, and its topology matches what is known of it. The
// expected numbers were established independently of isoquad (a separate script counting
// V - E + F and boundary loops on the raw files) and agree with the models' known shapes.
#include <gtest/gtest.h>
#include <fstream>

#include "corpus.hpp"
#include "io/read_mesh.hpp"
#include "prep/prepare.hpp"

using namespace isoquad;

namespace {

struct Known {
  const char* file;
  uint32_t vertices, edges, triangles, boundary_loops;
  int64_t euler, genus;
};

const Known kCorpus[] = {
    {"sphere.off", 162, 480, 320, 0, 2, 0},
    {"cactus.off", 620, 1854, 1236, 0, 2, 0},
    {"hand.off", 1197, 3585, 2390, 0, 2, 0},
    {"cow.off", 2904, 8706, 5804, 0, 2, 0},
    {"fandisk.off", 6475, 19419, 12946, 0, 2, 0},
    {"bunny00.off", 37706, 113112, 75408, 0, 2, 0},
    {"armadillo.off", 26002, 78000, 52000, 0, 2, 0},
    {"double-torus-example.off", 231, 699, 466, 0, -2, 2},
    {"eight.off", 315, 951, 634, 0, -2, 2},
    {"knot1.off", 3200, 9600, 6400, 0, 0, 1},
    {"rotor.off", 600, 1800, 1200, 0, 0, 1},
    {"elephant.off", 2775, 8337, 5558, 0, -4, 3},
    {"anchor.off", 519, 1575, 1050, 0, -6, 4},
    {"mesh_with_border.off", 548, 1561, 1014, 1, 1, 0},
    {"nefertiti.off", 299, 860, 562, 1, 1, 0},
    {"mushroom.off", 2337, 6944, 4608, 1, 1, 0},
    {"mech-holes-shark.off", 5246, 15440, 10192, 4, -2, 0},
    {"three_peaks.off", 1907, 5577, 3671, 1, 1, 0},
    {"cylinder.off", 1200, 3461, 2262, 1, 1, 0},
};

void PrintTo(const Known& k, std::ostream* os) { *os << k.file; }

class Corpus : public testing::TestWithParam<Known> {};

}  // namespace

TEST_P(Corpus, InfoMatchesKnownTopology) {
  const Known& k = GetParam();
  ISOQUAD_CORPUS_MESH(path, k.file);
  const ReadResult read = read_mesh(path);
  const PreparedMesh p = prepare(read.mesh, {.diagnose = true});
  EXPECT_FALSE(p.report.has_errors());
  ASSERT_EQ(p.components.size(), 1u);
  const TriMesh& m = p.components[0].mesh;
  EXPECT_EQ(m.num_vertices(), k.vertices);
  EXPECT_EQ(m.num_edges(), k.edges);
  EXPECT_EQ(m.num_faces(), k.triangles);
  EXPECT_EQ(m.boundary_loops().size(), k.boundary_loops);
  EXPECT_EQ(m.euler_characteristic(), k.euler);
  EXPECT_EQ(m.components()[0].genus(), k.genus);
  // The report (combinatorial count) and the TriMesh (halfedge structure) agree.
  const ComponentReport& r = p.report.components[0];
  EXPECT_EQ(r.euler, k.euler);
  EXPECT_EQ(r.genus, k.genus);
  EXPECT_EQ(r.boundary_loops, k.boundary_loops);
  // These corpus files are clean: nothing to weld, split or flip.
  EXPECT_EQ(p.report.welded_vertices, 0u);
  EXPECT_EQ(p.report.split_vertices, 0u);
  EXPECT_EQ(p.report.flipped_faces, 0u);
  EXPECT_NEAR(m.bounding_box().diagonal(), 1.0, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Corpus, Corpus, testing::ValuesIn(kCorpus), [](const auto& info) {
  std::string n = info.param.file;
  n = n.substr(0, n.find('.'));
  for (char& c : n)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return n;
});

TEST(Corpus, TestListMatchesCorpusFile) {
  // The parameterized tests and scripts/get-corpus must cover the same meshes.
  std::ifstream in(std::filesystem::path(ISOQUAD_SOURCE_DIR) / "bench" / "corpus.txt");
  std::vector<std::string> listed;
  for (std::string line; std::getline(in, line);) {
    line = line.substr(0, line.find('#'));
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    if (!line.empty()) listed.push_back(line);
  }
  const std::vector<std::string> tested(std::begin(test::kCorpusMeshes),
                                        std::end(test::kCorpusMeshes));
  EXPECT_EQ(listed, tested);
  EXPECT_EQ(listed.size(), std::size(kCorpus));
}
