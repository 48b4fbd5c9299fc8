// Layout benchmarks: corner assignment plus integer lengths for fandisk and bunny00 at about
// 1,500 and 20,000 quads (segmentation done once, outside the timing).
#include <benchmark/benchmark.h>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include "io/read_mesh.hpp"
#include "layout/layout.hpp"
#include "pipeline/sizing.hpp"
#include "prep/prepare.hpp"
#include "seg/segment.hpp"

namespace {

struct Prepared {
  isoquad::PreparedMesh mesh;
  isoquad::SegmentResult seg;
};

const Prepared* load(const char* name, double quads) {
  static std::map<std::pair<std::string, double>, Prepared> cache;
  const auto key = std::pair(std::string(name), quads);
  auto it = cache.find(key);
  if (it == cache.end()) {
    const char* dir = std::getenv("ISOQUAD_CORPUS_DIR");
    const auto path = std::filesystem::path(dir ? dir : ISOQUAD_SOURCE_DIR "/corpus") / name;
    if (!std::filesystem::exists(path)) return nullptr;
    Prepared p{isoquad::prepare(isoquad::read_mesh(path).mesh), {}};
    const auto& c = p.mesh.components.at(0);
    isoquad::SegmentOptions so;
    so.vsa.target_edge_length = isoquad::edge_length_for_quads(c.mesh, quads);
    so.meta.corner_window = so.vsa.target_edge_length;
    p.seg = isoquad::segment(c.mesh, c.feature, so);
    it = cache.emplace(key, std::move(p)).first;
  }
  return &it->second;
}

void BM_Layout(benchmark::State& state, const char* name) {
  const double quads = double(state.range(0));
  const Prepared* p = load(name, quads);
  if (!p) return state.SkipWithError("corpus missing: run scripts/get-corpus");
  isoquad::LayoutOptions o;
  o.quads = quads;
  isoquad::LayoutReport report;
  for (auto _ : state) {
    isoquad::MetaMesh meta = p->seg.meta;
    report = {};
    benchmark::DoNotOptimize(
        isoquad::solve_layout(p->seg.refined.mesh, p->seg.labels, p->seg.feature, meta, o, report));
  }
  state.counters["corner_ms"] = 1e3 * report.corner_seconds;
  state.counters["length_ms"] = 1e3 * report.length_seconds;
  state.counters["length_ilps"] = report.size_rounds;
  state.counters["patches"] = double(p->seg.num_patches);
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
