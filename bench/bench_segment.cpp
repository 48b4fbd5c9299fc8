// Segmentation benchmarks (issue: under 0.1 s for fandisk and under 1 s for bunny00 on one thread).
#include <benchmark/benchmark.h>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include "io/read_mesh.hpp"
#include "pipeline/sizing.hpp"
#include "prep/prepare.hpp"
#include "seg/segment.hpp"

namespace {

const isoquad::PreparedComponent* load(const char* name) {
  static std::map<std::string, isoquad::PreparedMesh> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    const char* dir = std::getenv("ISOQUAD_CORPUS_DIR");
    const auto path = std::filesystem::path(dir ? dir : ISOQUAD_SOURCE_DIR "/corpus") / name;
    if (!std::filesystem::exists(path)) return nullptr;
    it = cache.emplace(name, isoquad::prepare(isoquad::read_mesh(path).mesh)).first;
  }
  return &it->second.components.at(0);
}

isoquad::SegmentOptions options(const isoquad::TriMesh& m, uint32_t k) {
  isoquad::SegmentOptions o;
  o.vsa.patches = k;
  o.vsa.target_edge_length = isoquad::edge_length_for_quads(m, isoquad::default_quad_count(m));
  o.meta.corner_window = o.vsa.target_edge_length;
  return o;
}

void BM_Segment(benchmark::State& state, const char* name) {
  const auto* c = load(name);
  if (!c) return state.SkipWithError("corpus missing: run scripts/get-corpus");
  const auto o = options(c->mesh, uint32_t(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(isoquad::segment(c->mesh, c->feature, o));
}

void BM_Vsa(benchmark::State& state, const char* name) {
  const auto* c = load(name);
  if (!c) return state.SkipWithError("corpus missing: run scripts/get-corpus");
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
