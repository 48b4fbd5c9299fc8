// Layout benchmarks: corner assignment plus integer lengths for fandisk and bunny00 at about
// 1,500 and 20,000 quads (segmentation done once, outside the timing).
#include <benchmark/benchmark.h>
#include <map>
#include <string>

#include "bench_corpus.hpp"
#include "layout/layout.hpp"
#include "pipeline/sizing.hpp"
#include "seg/segment.hpp"

namespace {

// Segmentation for a quad count, once per (mesh, count).
const isoquad::SegmentResult* segmented(const char* name, double quads) {
  static std::map<std::pair<std::string, double>, isoquad::SegmentResult> cache;
  const auto key = std::pair(std::string(name), quads);
  auto it = cache.find(key);
  if (it == cache.end()) {
    const auto* c = isoquad::bench::corpus_component(name);
    if (!c) return nullptr;
    const auto o = isoquad::SegmentOptions::sized(isoquad::edge_length_for_quads(c->mesh, quads));
    it = cache.emplace(key, isoquad::segment(c->mesh, c->feature, o)).first;
  }
  return &it->second;
}

void BM_Layout(benchmark::State& state, const char* name) {
  const double quads = double(state.range(0));
  const isoquad::SegmentResult* seg = segmented(name, quads);
  if (!seg) return state.SkipWithError(isoquad::bench::kMissing);
  isoquad::LayoutOptions o;
  o.quads = quads;
  isoquad::LayoutReport report;
  for (auto _ : state) {
    isoquad::MetaMesh meta = seg->meta;
    report = {};
    benchmark::DoNotOptimize(
        isoquad::solve_layout(seg->refined.mesh, seg->labels, seg->feature, meta, o, report));
  }
  state.counters["corner_ms"] = 1e3 * report.corner_seconds;
  state.counters["refine_ms"] = 1e3 * report.refine_seconds;
  state.counters["length_ms"] = 1e3 * report.length_seconds;
  state.counters["length_ilps"] = report.size_rounds;
  state.counters["patches"] = double(seg->num_patches);
}

}  // namespace

BENCHMARK_CAPTURE(BM_Layout, fandisk, "fandisk.off")
    ->Arg(1500)
    ->Arg(20000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Layout, bunny00, "bunny00.off")
    ->Arg(1500)
    ->Arg(20000)
    ->Unit(benchmark::kMillisecond);
