// Layout benchmarks: corner assignment plus integer lengths for fandisk and bunny00 at about
// 1,500 and 20,000 quads, and for the field-aligned patches of the hand and the armadillo at 1,500
// (their free patches' corners by the feasibility-aware corner programs); segmentation done
// once, outside the timing.
#include <benchmark/benchmark.h>
#include <map>
#include <optional>
#include <string>

#include "bench_corpus.hpp"
#include "field/field_segment.hpp"
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

// The field-aligned patches for a quad count, once per (mesh, count); null where the mesh is
// missing or its traced layout fails (the pipeline would fall back to VSA).
const isoquad::FieldSegmentation* field_segmented(const char* name, double quads) {
  static std::map<std::pair<std::string, double>, std::optional<isoquad::FieldSegmentation>> cache;
  const auto key = std::pair(std::string(name), quads);
  auto it = cache.find(key);
  if (it == cache.end()) {
    std::optional<isoquad::FieldSegmentation> fs;
    if (const auto* c = isoquad::bench::corpus_component(name)) {
      isoquad::FieldLayoutLog log;
      const double h = isoquad::edge_length_for_quads(c->mesh, quads);
      fs = isoquad::field_segment(c->mesh, c->feature, h, log);
      if (!log.failure.empty()) fs.reset();
    }
    it = cache.emplace(key, std::move(fs)).first;
  }
  return it->second ? &*it->second : nullptr;
}

void BM_FieldLayout(benchmark::State& state, const char* name) {
  const double quads = double(state.range(0));
  const isoquad::FieldSegmentation* fs = field_segmented(name, quads);
  if (!fs) return state.SkipWithError("mesh missing or its field layout failed");
  isoquad::LayoutOptions o;
  o.quads = quads;
  o.given_corners = &fs->corners;
  o.preferred_corners = &fs->preferred;
  o.field_quarter_turns = &fs->quarter_turns;
  isoquad::LayoutReport report;
  for (auto _ : state) {
    isoquad::MetaMesh meta = fs->seg.meta;
    report = {};
    benchmark::DoNotOptimize(isoquad::solve_layout(fs->seg.refined.mesh, fs->seg.labels,
                                                   fs->seg.feature, meta, o, report));
  }
  state.counters["corner_ms"] = 1e3 * report.corner_seconds;
  state.counters["length_ms"] = 1e3 * report.length_seconds;
  state.counters["patches"] = double(fs->seg.num_patches);
}

}  // namespace

BENCHMARK_CAPTURE(BM_FieldLayout, hand, "hand.off")->Arg(1500)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FieldLayout, armadillo, "armadillo.off")
    ->Arg(1500)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Layout, fandisk, "fandisk.off")
    ->Arg(1500)
    ->Arg(20000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Layout, bunny00, "bunny00.off")
    ->Arg(1500)
    ->Arg(20000)
    ->Unit(benchmark::kMillisecond);
