// Reader and preparation benchmarks on corpus meshes (run scripts/get-corpus first).
#include <benchmark/benchmark.h>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bench_corpus.hpp"
#include "prep/prepare.hpp"

namespace {

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void BM_ReadFile(benchmark::State& state, const char* name) {
  const auto path = isoquad::bench::corpus_path(name);
  if (!std::filesystem::exists(path)) return state.SkipWithError(isoquad::bench::kMissing);
  for (auto _ : state) benchmark::DoNotOptimize(isoquad::read_mesh(path));
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(std::filesystem::file_size(path)));
}

void BM_ParseMemory(benchmark::State& state, const char* name) {
  const auto path = isoquad::bench::corpus_path(name);
  if (!std::filesystem::exists(path)) return state.SkipWithError(isoquad::bench::kMissing);
  const std::string bytes = slurp(path);
  for (auto _ : state)
    benchmark::DoNotOptimize(isoquad::read_mesh_from_memory(bytes, isoquad::MeshFormat::off, name));
}

void BM_Prepare(benchmark::State& state, const char* name) {
  const auto path = isoquad::bench::corpus_path(name);
  if (!std::filesystem::exists(path)) return state.SkipWithError(isoquad::bench::kMissing);
  const auto read = isoquad::read_mesh(path);
  for (auto _ : state) benchmark::DoNotOptimize(isoquad::prepare(read.mesh));
}

}  // namespace

BENCHMARK_CAPTURE(BM_ReadFile, bunny00, "bunny00.off")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ReadFile, fandisk, "fandisk.off")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ParseMemory, bunny00, "bunny00.off")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Prepare, bunny00, "bunny00.off")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Prepare, fandisk, "fandisk.off")->Unit(benchmark::kMillisecond);
