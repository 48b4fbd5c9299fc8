// The library's remesh around the stages: its progress (isoquad::Progress) and the topology check
// on each component's quads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "corpus.hpp"
#include "io/read_mesh.hpp"
#include "isoquad/error.hpp"
#include "metrics/quality.hpp"
#include "pipeline/remesh.hpp"
#include "shapes.hpp"

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

Topology topology(const PolyMesh& m) {
  return topology_of(m, nullptr, nullptr, nullptr, nullptr, nullptr);
}

// A quad torus: n x n quads around both circles.
PolyMesh quad_torus(uint32_t n) {
  PolyMesh m;
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t j = 0; j < n; ++j) {
      const double u = 2 * M_PI * i / n, v = 2 * M_PI * j / n;
      m.positions.push_back(
          {(2 + std::cos(v)) * std::cos(u), (2 + std::cos(v)) * std::sin(u), std::sin(v)});
    }
  const auto id = [n](uint32_t i, uint32_t j) { return (i % n) * n + j % n; };
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t j = 0; j < n; ++j)
      m.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return m;
}

PolyMesh without_last_face(const PolyMesh& m) {
  PolyMesh out;
  out.positions = m.positions;
  for (std::size_t f = 0; f + 1 < m.num_faces(); ++f) {
    out.add_face(m.face(f));
  }
  return out;
}

PolyMesh twice(const PolyMesh& m) {
  PolyMesh out = m;
  const auto n = uint32_t(m.positions.size());
  for (const Vec3& p : m.positions) out.positions.push_back(p + Vec3{3, 0, 0});
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    std::vector<uint32_t> vs;
    for (const uint32_t v : m.face(f)) vs.push_back(v + n);
    out.add_face(vs);
  }
  return out;
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

TEST(Remesh, TopologyChangeSaysWhatChanged) {
  const PolyMesh cube = test::cube_quads();
  const Topology closed = topology(cube), open = topology(without_last_face(cube));
  EXPECT_EQ(topology_change(closed, closed), "");
  EXPECT_EQ(topology_change(open, closed), "boundary loops 1 -> 0");  // a hole closed
  EXPECT_EQ(topology_change(closed, open), "boundary loops 0 -> 1");
  EXPECT_EQ(topology_change(closed, topology(quad_torus(6))), "genus 0 -> 1");
  EXPECT_EQ(topology_change(closed, topology(twice(cube))), "connected pieces 1 -> 2");
  EXPECT_EQ(topology_change(topology(quad_torus(6)), open), "genus 1 -> 0, boundary loops 0 -> 1");
}

TEST(Remesh, TopologyChangeIsAnErrorUnlessAllowed) {
  const PolyMesh cube = test::cube_quads();
  const Topology closed = topology(cube), open = topology(without_last_face(cube));
  EXPECT_FALSE(check_component_topology(2, closed, closed, false));
  EXPECT_FALSE(check_component_topology(2, closed, closed, true));
  try {
    check_component_topology(2, open, closed, false);
    FAIL() << "a hole closed passed";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), "E603");
    EXPECT_EQ(e.kind(), ErrorKind::extraction);
    const std::string what = e.what();
    EXPECT_NE(what.find("component 2:"), std::string::npos) << what;
    EXPECT_NE(what.find("boundary loops 1 -> 0"), std::string::npos) << what;
    EXPECT_NE(what.find("--allow-topology-change"), std::string::npos) << what;
  }
  const auto allowed = check_component_topology(2, open, closed, true);
  ASSERT_TRUE(allowed);
  EXPECT_EQ(allowed->code, "W113");
  EXPECT_EQ(allowed->severity, InputIssue::Severity::warning);
  EXPECT_NE(allowed->message.find("component 2:"), std::string::npos) << allowed->message;
  EXPECT_NE(allowed->message.find("boundary loops 1 -> 0"), std::string::npos);
}

TEST(Remesh, AllowTopologyChangeIsEchoedInTheReport) {
  const PolyMesh sphere = read_mesh(test::data_dir() / "sphere.off").mesh;
  RemeshOptions o;
  o.quads = 300;
  o.quality = false;
  EXPECT_NE(remesh_polymesh(sphere, o).report.find("\"allow_topology_change\": false"),
            std::string::npos);
  o.allow_topology_change = true;
  const std::string report = remesh_polymesh(sphere, o).report;
  EXPECT_NE(report.find("\"allow_topology_change\": true"), std::string::npos);
  EXPECT_EQ(report.find("W113"), std::string::npos);  // the sphere's quads keep its topology
}
