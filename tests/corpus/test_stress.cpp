// The generated stress set of issue 32 (tests/support/stress_shapes.hpp): 104 shapes in 8
// families, each scaled to a bounding-box diagonal of 1e-3 or 1e3, remeshed without an error and
// valid: pure quad, manifold, oriented, the input's components, boundary loops and Euler
// characteristic, no quad with a scaled Jacobian <= 0.001 against its own normal, the count
// within 10% of the one asked for, and the output at the input's scale. CI runs 16 of them
// (StressCi) at 1,500 quads; the whole set at 1,500 quads and at the default size (StressFull)
// runs only with ISOQUAD_STRESS_FULL=1 (scripts/test --full), and there the mean scaled Jacobian
// must also reach 0.85, issue 32's bound. ISOQUAD_STRESS_SEGMENTATION=field runs them with the
// field-aligned layout. docs/stress.md has the figures of both layouts.
#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <ostream>
#include <string>

#include <fmt/format.h>

#include "isoquad/error.hpp"
#include "metrics/quality.hpp"
#include "pipeline/remesh.hpp"
#include "quad_checks.hpp"
#include "stress_shapes.hpp"

using namespace isoquad;
using test::StressCase;

namespace {

// Issue 32's bound on the mean scaled Jacobian of each output.
constexpr double kMinMeanScaledJacobian = 0.85;

struct StressRun {
  const StressCase* shape;
  double diagonal;
  double quads;  // 0: the default size
};

std::string run_name(const StressRun& r) {
  return fmt::format("{}_{}_{}", r.shape->name, r.diagonal < 1 ? "small" : "large",
                     r.quads > 0 ? fmt::format("q{}", r.quads) : "default");
}
std::string test_name(const testing::TestParamInfo<StressRun>& info) {
  return run_name(info.param);
}
void PrintTo(const StressRun& r, std::ostream* out) { *out << run_name(r); }

// Quads with a scaled Jacobian <= 0.001 against their own normal that VSA layouts leave on the CI
// subset at 1,500 quads (run name: count). None since the untangler counts own-normal corners
// (measured 2026-12-05; before, 16 on six runs: the helix's and the knot's thin tubes, the
// genus-5 tori's and the frame's junctions, a thick plate's hole, a blob's bump). Validity
// forbids them; a run listed here may have no more.
const std::map<std::string, uint32_t> kKnownInvalid = {};

double diagonal_of(const PolyMesh& m) {
  Box3 box;
  for (const Vec3& p : m.positions) box.add(p);
  return box.diagonal();
}

// The run and the validity of issue 32, but for `known_invalid` quads at most 0.001; with
// `mean_bound`, the mean scaled Jacobian too.
void expect_valid_remesh(const StressRun& r, uint32_t known_invalid, bool mean_bound) {
  SCOPED_TRACE(r.shape->name + ": " + r.shape->params);
  const PolyMesh input = test::scaled_to_diagonal(test::build_stress_mesh(*r.shape), r.diagonal);
  RemeshOptions o;
  o.quads = r.quads;
  o.quality = false;
  if (const char* s = std::getenv("ISOQUAD_STRESS_SEGMENTATION")) o.segmentation = s;
  RemeshRun run;
  try {
    run = remesh_run(input, o);
  } catch (const Error& e) {
    FAIL() << e.code() << ": " << e.what();
  }
  const PolyMesh& quads = run.result.quads;
  const QualityReport q = measure_quality(quads, &input);
  test::expect_valid_quad_mesh(q);
  EXPECT_LE(q.sj_invalid, known_invalid)
      << "quads with scaled Jacobian <= 0.001 against their own normal "
      << "(min " << q.sj_min << ")";
  if (r.quads > 0) {
    EXPECT_NEAR(double(quads.num_faces()), r.quads, 0.1 * r.quads);
  }
  EXPECT_NEAR(diagonal_of(quads) / r.diagonal, 1.0, 0.1);
  if (mean_bound) {
    EXPECT_GE(q.sj_mean, kMinMeanScaledJacobian);
  }
  testing::Test::RecordProperty("quads", int(quads.num_faces()));
  testing::Test::RecordProperty("sj_mean_permille", int(1000 * q.sj_mean));
  testing::Test::RecordProperty("sj_invalid", int(q.sj_invalid));
}

// The CI subset: 2 shapes a family, the first at diagonal 1e-3 and the second at 1e3.
std::vector<StressRun> ci_runs() {
  std::vector<StressRun> runs;
  for (const StressCase* c : test::stress_ci_cases())
    runs.push_back({c, runs.size() % 2 ? 1e3 : 1e-3, 1500});
  return runs;
}

std::vector<StressRun> full_runs() {
  std::vector<StressRun> runs;
  for (const StressCase& c : test::stress_cases())
    for (double quads : {1500.0, 0.0})
      for (double d : {1e-3, 1e3}) runs.push_back({&c, d, quads});
  return runs;
}

class StressCi : public testing::TestWithParam<StressRun> {};
class StressFull : public testing::TestWithParam<StressRun> {};

}  // namespace

// At least 100 shapes, 8 families of at least 10; each one manifold component of its intended
// topology (build_stress_mesh throws otherwise), of 2k to 30k triangles; the same mesh from
// the same parameters.
TEST(StressShapes, EveryShapeHasItsIntendedTopology) {
  std::map<std::string, int> families;
  for (const StressCase& c : test::stress_cases()) {
    SCOPED_TRACE(c.name + ": " + c.params);
    ++families[c.family];
    PolyMesh m;
    ASSERT_NO_THROW(m = test::build_stress_mesh(c));
    EXPECT_GE(m.num_faces(), 2000u);
    EXPECT_LE(m.num_faces(), 30000u);
    if (c.name.ends_with("_01")) {
      const PolyMesh again = c.build();
      EXPECT_EQ(again.positions, m.positions);
      EXPECT_EQ(again.face_vertices, m.face_vertices);
    }
  }
  EXPECT_GE(test::stress_cases().size(), 100u);
  EXPECT_EQ(families.size(), 8u);
  for (const auto& [family, count] : families) EXPECT_GE(count, 10) << family;
}

TEST_P(StressCi, RemeshedValid) {
  const auto known = kKnownInvalid.find(run_name(GetParam()));
  expect_valid_remesh(GetParam(), known == kKnownInvalid.end() ? 0 : known->second, false);
}

TEST_P(StressFull, RemeshedValid) {
  if (!std::getenv("ISOQUAD_STRESS_FULL")) GTEST_SKIP() << "ISOQUAD_STRESS_FULL=1 runs it";
  expect_valid_remesh(GetParam(), 0, true);
}

INSTANTIATE_TEST_SUITE_P(Stress, StressCi, testing::ValuesIn(ci_runs()), test_name);
INSTANTIATE_TEST_SUITE_P(Stress, StressFull, testing::ValuesIn(full_runs()), test_name);
