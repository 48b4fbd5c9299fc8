// The library's remesh around the stages: its progress (isoquad::Progress).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <thread>
#include <vector>

#include "corpus.hpp"
#include "io/read_mesh.hpp"
#include "pipeline/remesh.hpp"

namespace {

using namespace isoquad;

// The stage names in the order of their first report, as remesh.hpp documents them.
const std::vector<std::string> kStages = {"prepare", "segment", "layout",  "map",
                                          "extract", "repair",  "quality", "done"};

std::vector<std::string> first_reports(const std::vector<Progress>& calls) {
  std::vector<std::string> stages;
  for (const Progress& p : calls)
    if (std::find(stages.begin(), stages.end(), p.stage) == stages.end()) stages.push_back(p.stage);
  return stages;
}

}  // namespace

TEST(Remesh, ProgressReportsEveryStageInOrderAndNeverGoesDown) {
  const PolyMesh sphere = read_mesh(test::data_dir() / "sphere.off").mesh;
  for (const std::string segmentation : {"vsa", "field"}) {
    SCOPED_TRACE(segmentation);
    RemeshOptions o;
    o.quads = 300;
    o.segmentation = segmentation;
    std::vector<Progress> calls;
    const std::thread::id caller = std::this_thread::get_id();
    bool on_caller = true;
    remesh_run(sphere, o, false, {}, [&](const Progress& p) {
      on_caller = on_caller && std::this_thread::get_id() == caller;
      calls.push_back(p);
    });
    ASSERT_FALSE(calls.empty());
    EXPECT_TRUE(on_caller);
    EXPECT_EQ(first_reports(calls), kStages);
    for (std::size_t k = 1; k < calls.size(); ++k)
      EXPECT_GE(calls[k].fraction, calls[k - 1].fraction)
          << calls[k - 1].stage << " -> " << calls[k].stage;
    EXPECT_EQ(calls.front().fraction, 0);
    EXPECT_EQ(calls.back().fraction, 1);
    EXPECT_EQ(calls.back().stage, "done");
    // Each stage begun is reported once with no message, then lines said with one.
    EXPECT_TRUE(std::any_of(calls.begin(), calls.end(), [](const Progress& p) {
      return p.message.rfind("component 0: segment", 0) == 0;
    }));
  }
}

TEST(Remesh, ProgressChangesNothingInTheOutput) {
  const PolyMesh sphere = read_mesh(test::data_dir() / "sphere.off").mesh;
  RemeshOptions o;
  o.quads = 300;
  o.quality = false;
  const PolyMesh with = remesh_polymesh(sphere, o, false, {}, [](const Progress&) {}).quads;
  const PolyMesh without = remesh_polymesh(sphere, o).quads;
  EXPECT_EQ(with.positions, without.positions);
  EXPECT_EQ(with.face_group, without.face_group);
  ASSERT_EQ(with.num_faces(), without.num_faces());
  for (std::size_t f = 0; f < with.num_faces(); ++f)
    EXPECT_TRUE(std::equal(with.face(f).begin(), with.face(f).end(), without.face(f).begin()));
}
