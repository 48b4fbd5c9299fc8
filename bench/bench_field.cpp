// Cross field benchmark (issue: the field plus its tracing at most a third of bunny00's remesh
// run, so the field itself well under 0.4 s): feature-conflict splits, smoothing, guidance,
// solve and singularities, as `isoquad field MESH --quads 1500` runs them. Reading and
// preparing the mesh are outside the timing.
#include <benchmark/benchmark.h>

#include "bench_corpus.hpp"
#include "field/cross_field.hpp"
#include "pipeline/sizing.hpp"

namespace {

void BM_CrossField(benchmark::State& state, const char* name) {
  const auto* c = isoquad::bench::corpus_component(name);
  if (!c) return state.SkipWithError(isoquad::bench::kMissing);
  isoquad::CrossFieldOptions o;
  o.edge_length = isoquad::edge_length_for_quads(c->mesh, double(state.range(0)));
  std::size_t singular = 0;
  for (auto _ : state) {
    isoquad::EdgeData<char> feature = c->feature;
    const isoquad::RefinedMesh refined =
        isoquad::split_constraint_conflicts(isoquad::identity_refinement(c->mesh), feature);
    const isoquad::CrossField field = isoquad::compute_cross_field(refined.mesh, feature, o);
    singular = field.singular.size();
    benchmark::DoNotOptimize(field.energy);
  }
  state.counters["faces"] = double(c->mesh.num_faces());
  state.counters["singular"] = double(singular);
}

}  // namespace

BENCHMARK_CAPTURE(BM_CrossField, bunny00, "bunny00.off")->Arg(1500)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CrossField, armadillo, "armadillo.off")
    ->Arg(1500)
    ->Unit(benchmark::kMillisecond);
