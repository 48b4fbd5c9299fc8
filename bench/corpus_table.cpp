// The corpus benchmark: every mesh of bench/corpus.txt remeshed with the default options (or a
// quad count), measured by `isoquad quality`, and printed as one Markdown table: quads,
// irregular vertices, scaled Jacobian (min and mean), quads folded against the surface,
// two-sided Hausdorff distance, and the median wall time of the remesh over --repeat runs. The
// meshes run one after the other (one remesh at a time, so that the times are comparable).
//
//   build/release/bench/corpus_table [--quads N] [--repeat R] [--fold-rounds F] [--mesh NAME]...
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <chrono>
#include <fstream>
#include <string>
#include <vector>

#include "bench_corpus.hpp"
#include "isoquad/error.hpp"
#include "metrics/quality.hpp"
#include "pipeline/remesh.hpp"

int main(int argc, char** argv) {
  CLI::App app("Remesh the corpus and print the quality table");
  double quads = 0, tolerance = isoquad::RemeshOptions{}.tolerance;
  uint32_t repeat = 1, fold_rounds = isoquad::RemeshOptions{}.fold_rounds;
  std::vector<std::string> only;
  app.add_option("--quads", quads, "Target quad count (default: each mesh's default size)");
  app.add_option("--repeat", repeat, "Remesh runs per mesh; the time is their median")
      ->check(CLI::Range(1u, 50u))
      ->capture_default_str();
  app.add_option("--fold-rounds", fold_rounds, "Rounds of more quads where quads still fold")
      ->capture_default_str();
  app.add_option("--tolerance", tolerance,
                 "At the default size: more quads while farther than this fraction of the "
                 "diagonal (remesh --tolerance; not with --quads)")
      ->capture_default_str();
  app.add_option("--mesh", only, "Only these corpus meshes (file names)");
  CLI11_PARSE(app, argc, argv);

  std::vector<std::string> names;
  std::ifstream list(std::string(ISOQUAD_SOURCE_DIR) + "/bench/corpus.txt");
  for (std::string line; std::getline(list, line);) {
    line = line.substr(0, line.find('#'));
    line.erase(std::remove_if(line.begin(), line.end(),
                              [](unsigned char ch) { return std::isspace(ch) != 0; }),
               line.end());
    if (!line.empty() && (only.empty() || std::find(only.begin(), only.end(), line) != only.end()))
      names.push_back(line);
  }
  for (const std::string& n : only)
    if (std::find(names.begin(), names.end(), n) == names.end()) {
      fmt::print(stderr, "{} is not in bench/corpus.txt\n", n);
      return 2;
    }
  fmt::print("| mesh | quads | irregular | SJ min | SJ mean | folded | Hausdorff % | time s |\n");
  fmt::print("|---|---|---|---|---|---|---|---|\n");
  uint32_t folded = 0, within2 = 0, failed = 0;
  for (const std::string& name : names) {
    const auto path = isoquad::bench::corpus_path(name.c_str());
    if (!std::filesystem::exists(path)) {
      fmt::print("| {} | {} | | | | | | |\n", name, isoquad::bench::kMissing);
      ++failed;
      continue;
    }
    try {
      const isoquad::ReadResult input = isoquad::read_mesh(path);
      isoquad::RemeshOptions o;
      o.quads = quads;
      o.quality = false;
      o.fold_rounds = fold_rounds;
      o.tolerance = tolerance;
      std::vector<double> seconds;
      isoquad::PolyRemesh result;
      for (uint32_t r = 0; r < repeat; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        result = isoquad::remesh_polymesh(input.mesh, o, input.unshared_vertices);
        seconds.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      }
      std::sort(seconds.begin(), seconds.end());
      const isoquad::QualityReport q = isoquad::measure_quality(result.quads, &input.mesh);
      folded += q.sj_surface_nonpositive;
      within2 += q.hausdorff <= 0.02;
      fmt::print("| {} | {} | {} | {:.3f} | {:.3f} | {} | {:.2f} | {:.2f} |\n",
                 name.substr(0, name.rfind('.')), q.faces, q.irregular, q.sj_min, q.sj_mean,
                 q.sj_surface_nonpositive, 100 * q.hausdorff, seconds[seconds.size() / 2]);
    } catch (const isoquad::Error& e) {
      fmt::print("| {} | FAILED: {} {} | | | | | | |\n", name, e.code(), e.what());
      ++failed;
    }
  }
  fmt::print(
      "\n{} meshes: {} quads folded against the surface, {} within 2% Hausdorff, {} failed\n",
      names.size(), folded, within2, failed);
  return failed > 0 ? 1 : 0;
}
