// Segmentation benchmarks (issue: under 0.1 s for fandisk and under 1 s for bunny00 on one thread).
#include <benchmark/benchmark.h>

#include "bench_corpus.hpp"
#include "pipeline/sizing.hpp"
#include "seg/segment.hpp"

namespace {

isoquad::SegmentOptions options(const isoquad::TriMesh& m, uint32_t k) {
  return isoquad::SegmentOptions::sized(
      isoquad::edge_length_for_quads(m, isoquad::default_quad_count(m.num_faces())), k);
}

void BM_Segment(benchmark::State& state, const char* name) {
  const auto* c = isoquad::bench::corpus_component(name);
  if (!c) return state.SkipWithError(isoquad::bench::kMissing);
  const auto o = options(c->mesh, uint32_t(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(isoquad::segment(c->mesh, c->feature, o));
}

void BM_Vsa(benchmark::State& state, const char* name) {
  const auto* c = isoquad::bench::corpus_component(name);
  if (!c) return state.SkipWithError(isoquad::bench::kMissing);
  const auto o = options(c->mesh, uint32_t(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(isoquad::segment_vsa(c->mesh, c->feature, o.vsa));
}

}  // namespace

BENCHMARK_CAPTURE(BM_Segment, fandisk, "fandisk.off")
    ->Arg(0)
    ->Arg(30)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Segment, bunny00, "bunny00.off")
    ->Arg(0)
    ->Arg(30)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Vsa, fandisk, "fandisk.off")->Arg(30)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Vsa, bunny00, "bunny00.off")->Arg(30)->Unit(benchmark::kMillisecond);
