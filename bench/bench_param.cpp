// Parametrization benchmarks (issue 5): adaptive stiffening against the paper's bisection on
// fandisk and bunny00 at 1,500 quads: time, numeric factorizations, and the mean angle
// distortion near seams. Segmentation and layout are done once, outside the timing. Also the
// end-to-end pipeline (segmentation to extraction) at 1,500 quads.
#include <benchmark/benchmark.h>

#include <map>
#include <string>

#include "bench_corpus.hpp"
#include "pipeline/pipeline.hpp"

namespace {

const isoquad::ComponentRun* laid_out(const char* name) {
  static std::map<std::string, isoquad::ComponentRun> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    const auto path = isoquad::bench::corpus_path(name);
    if (!std::filesystem::exists(path)) return nullptr;
    static std::map<std::string, isoquad::PreparedMesh> preps;
    const auto& prep =
        preps.emplace(name, isoquad::prepare(isoquad::read_mesh(path).mesh)).first->second;
    isoquad::PipelineOptions o;
    o.quads = 1500;
    o.last = isoquad::Stage::layout;
    it = cache.emplace(name, isoquad::run_component(prep, 0, o)).first;
  }
  return &it->second;
}

void BM_Param(benchmark::State& state, const char* name, isoquad::RelaxMode mode) {
  const isoquad::ComponentRun* run = laid_out(name);
  if (!run) return state.SkipWithError(isoquad::bench::kMissing);
  isoquad::ParamOptions o;
  o.relax = mode;
  isoquad::ParamReport report;
  for (auto _ : state) {
    report = {};
    benchmark::DoNotOptimize(isoquad::parametrize(run->seg.refined.mesh, run->seg.labels,
                                                  run->seg.meta, run->layout, o, report));
  }
  state.counters["factorizations"] = report.factorizations;
  state.counters["fell_back"] = report.fell_back_to_locked;
  state.counters["seam_distortion"] = report.seam_angle_distortion;
  state.counters["unknowns"] = report.unknowns;
}

void BM_Remesh(benchmark::State& state, const char* name) {
  const auto path = isoquad::bench::corpus_path(name);
  if (!std::filesystem::exists(path)) return state.SkipWithError(isoquad::bench::kMissing);
  const isoquad::ReadResult in = isoquad::read_mesh(path);
  isoquad::PipelineOptions o;
  o.quads = 1500;
  for (auto _ : state) {
    const isoquad::PreparedMesh prep = isoquad::prepare(in.mesh);
    benchmark::DoNotOptimize(isoquad::run_pipeline(prep, o));
  }
}

}  // namespace

BENCHMARK_CAPTURE(BM_Param, fandisk_adaptive, "fandisk.off", isoquad::RelaxMode::adaptive)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Param, fandisk_bisection, "fandisk.off", isoquad::RelaxMode::bisection)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Param, bunny00_adaptive, "bunny00.off", isoquad::RelaxMode::adaptive)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Param, bunny00_bisection, "bunny00.off", isoquad::RelaxMode::bisection)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Remesh, fandisk, "fandisk.off")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Remesh, bunny00, "bunny00.off")->Unit(benchmark::kMillisecond);
