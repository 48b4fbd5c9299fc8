// The corpus benchmark: every mesh of bench/corpus.txt remeshed with the default options (or a
// quad count, or the field-aligned segmentation), measured by `isoquad quality`, and printed as
// one Markdown table: quads, irregular vertices, scaled Jacobian (min and mean against each
// quad's own normal, quads at most 0.001 there), quads folded against the surface, aspect ratio
// (mean, 95th percentile, share above 2), area CV, feature coverage, two-sided Hausdorff
// distance, and the median wall time of the remesh over --repeat runs. The meshes run one after
// the other (one remesh at a time, so that the times are comparable). --json FILE also writes
// every mesh's whole quality report.
//
//   build/release/bench/corpus_table [--quads N] [--segmentation vsa|field] [--repeat R]
//                                    [--fold-rounds F] [--tolerance T] [--json FILE] [--mesh
//                                    NAME]...
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench_corpus.hpp"
#include "io/report_json.hpp"
#include "isoquad/error.hpp"
#include "metrics/quality.hpp"
#include "pipeline/remesh.hpp"

namespace {

std::vector<std::string> corpus_names(const std::vector<std::string>& only) {
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
  return names;
}

double median(std::vector<double> x) {
  if (x.empty()) return 0;
  std::sort(x.begin(), x.end());
  const std::size_t n = x.size();
  return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}

// Which segmentation laid out each component ("field", or "vsa" where the field's fell back).
std::vector<std::string> layout_sources(const std::string& report) {
  std::vector<std::string> sources;
  const nlohmann::json j = nlohmann::json::parse(report);
  for (const auto& c : j.at("components")) sources.push_back(c.value("layout_source", "vsa"));
  return sources;
}

std::string empty_cells(int n) {
  std::string cells;
  for (int i = 0; i < n; ++i) cells += " |";
  return cells;
}

struct Totals {
  uint32_t invalid = 0, invalid_meshes = 0, folded = 0, within2 = 0, failed = 0;
  std::vector<double> sj_mean, aspect_above_2, area_cv, seconds;
};

void print_row(const std::string& mesh, const isoquad::QualityReport& q, double seconds,
               const std::string& layout) {
  const std::string features =
      q.feature_length > 0 ? fmt::format("{:.1f}", 100 * q.feature_coverage) : "–";
  fmt::print(
      "| {} | {} | {} | {:.3f} | {:.3f} | {} | {} | {:.2f} | {:.2f} | {:.1f} | {:.3f} | {} | "
      "{:.2f} | {:.2f} |{}\n",
      mesh, q.faces, q.irregular, q.sj_min, q.sj_mean, q.sj_invalid, q.sj_surface_nonpositive,
      q.aspect_mean, q.aspect_p95, q.aspect_above_2, q.area_cv, features, 100 * q.hausdorff,
      seconds, layout.empty() ? "" : " " + layout + " |");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Remesh the corpus and print the quality table");
  double quads = 0, tolerance = isoquad::RemeshOptions{}.tolerance;
  uint32_t repeat = 1, fold_rounds = isoquad::RemeshOptions{}.fold_rounds,
           smooth = isoquad::RemeshOptions{}.smooth;
  std::string segmentation = isoquad::RemeshOptions{}.segmentation, json_path;
  std::vector<std::string> only;
  app.add_option("--quads", quads, "Target quad count (default: each mesh's default size)");
  app.add_option("--segmentation", segmentation, "How the surface is cut into patches")
      ->check(CLI::IsMember({"vsa", "field"}))
      ->capture_default_str();
  app.add_option("--repeat", repeat, "Remesh runs per mesh; the time is their median")
      ->check(CLI::Range(1u, 50u))
      ->capture_default_str();
  app.add_option("--fold-rounds", fold_rounds, "Rounds of more quads where quads still fold")
      ->capture_default_str();
  app.add_option("--smooth", smooth,
                 "Tangential smoothing sweeps after extraction (remesh --smooth)")
      ->capture_default_str();
  app.add_option("--tolerance", tolerance,
                 "At the default size: more quads while farther than this fraction of the "
                 "diagonal (remesh --tolerance; not with --quads)")
      ->capture_default_str();
  app.add_option("--json", json_path, "Also write every mesh's quality report to this file");
  app.add_option("--mesh", only, "Only these corpus meshes (file names)");
  CLI11_PARSE(app, argc, argv);

  const std::vector<std::string> names = corpus_names(only);
  for (const std::string& n : only)
    if (std::find(names.begin(), names.end(), n) == names.end()) {
      fmt::print(stderr, "{} is not in bench/corpus.txt\n", n);
      return 2;
    }
  const bool field = segmentation == "field";
  fmt::print(
      "| mesh | quads | irregular | SJ min | SJ mean | SJ ≤ 0.001 (own normal) | folded (surface) "
      "| aspect mean | aspect p95 | aspect > 2 % | area CV | features % | Hausdorff % | time s "
      "|{}\n",
      field ? " layout |" : "");
  fmt::print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|{}\n", field ? "---|" : "");
  Totals t;
  nlohmann::json meshes = nlohmann::json::array();
  for (const std::string& name : names) {
    const std::string mesh = name.substr(0, name.rfind('.'));
    const auto path = isoquad::bench::corpus_path(name.c_str());
    if (!std::filesystem::exists(path)) {
      fmt::print("| {} | {} |{}\n", name, isoquad::bench::kMissing, empty_cells(field ? 13 : 12));
      meshes.push_back({{"mesh", mesh}, {"error", isoquad::bench::kMissing}});
      ++t.failed;
      continue;
    }
    try {
      const isoquad::ReadResult input = isoquad::read_mesh(path);
      isoquad::RemeshOptions o;
      o.quads = quads;
      o.segmentation = segmentation;
      o.quality = false;
      o.fold_rounds = fold_rounds;
      o.smooth = smooth;
      o.tolerance = tolerance;
      std::vector<double> seconds;
      isoquad::PolyRemesh result;
      for (uint32_t r = 0; r < repeat; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        result = isoquad::remesh_polymesh(input.mesh, o, input.unshared_vertices);
        seconds.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      }
      const double time = median(seconds);
      isoquad::QualityOptions measure;
      measure.feature_angle_deg = o.feature_angle_deg;
      const isoquad::QualityReport q = isoquad::measure_quality(result.quads, &input.mesh, measure);
      const std::vector<std::string> sources = layout_sources(result.report);
      t.invalid += q.sj_invalid;
      t.invalid_meshes += q.sj_invalid > 0;
      t.folded += q.sj_surface_nonpositive;
      t.within2 += q.hausdorff <= 0.02;
      t.sj_mean.push_back(q.sj_mean);
      t.aspect_above_2.push_back(q.aspect_above_2);
      t.area_cv.push_back(q.area_cv);
      t.seconds.push_back(time);
      std::string layout;
      for (const std::string& s : sources) layout += (layout.empty() ? "" : ", ") + s;
      print_row(mesh, q, time, field ? layout : "");
      meshes.push_back({{"mesh", mesh},
                        {"seconds", time},
                        {"layout_source", sources},
                        {"quality", nlohmann::json(q)}});
    } catch (const isoquad::Error& e) {
      fmt::print("| {} | FAILED: {} {} |{}\n", name, e.code(), e.what(),
                 empty_cells(field ? 13 : 12));
      meshes.push_back({{"mesh", mesh}, {"error", fmt::format("{} {}", e.code(), e.what())}});
      ++t.failed;
    }
  }
  double total_seconds = 0;
  for (const double s : t.seconds) total_seconds += s;
  const double lowest_sj =
      t.sj_mean.empty() ? 0 : *std::min_element(t.sj_mean.begin(), t.sj_mean.end());
  fmt::print(
      "\n{} meshes ({}): {} quads with SJ ≤ 0.001 against their own normal, on {} meshes; {} "
      "quads folded against the surface; SJ mean median {:.3f}, lowest {:.3f}; aspect > 2 median "
      "{:.1f}%; area CV median {:.3f}; {} within 2% Hausdorff; {:.1f} s remeshing; {} failed\n",
      names.size(), segmentation, t.invalid, t.invalid_meshes, t.folded, median(t.sj_mean),
      lowest_sj, median(t.aspect_above_2), median(t.area_cv), t.within2, total_seconds, t.failed);
  if (!json_path.empty()) {
    const nlohmann::json j = {{"options",
                               {{"quads", quads},
                                {"segmentation", segmentation},
                                {"repeat", repeat},
                                {"fold_rounds", fold_rounds},
                                {"smooth", smooth},
                                {"tolerance", tolerance}}},
                              {"meshes", meshes},
                              {"totals",
                               {{"meshes", names.size()},
                                {"sj_at_most_0.001", t.invalid},
                                {"meshes_with_sj_at_most_0.001", t.invalid_meshes},
                                {"folded_surface", t.folded},
                                {"sj_mean_median", median(t.sj_mean)},
                                {"sj_mean_lowest", lowest_sj},
                                {"aspect_percent_above_2_median", median(t.aspect_above_2)},
                                {"area_cv_median", median(t.area_cv)},
                                {"within_2_percent_hausdorff", t.within2},
                                {"seconds", total_seconds},
                                {"failed", t.failed}}}};
    std::ofstream out(json_path);
    out << j.dump(2) << '\n';
    if (!out) {
      fmt::print(stderr, "cannot write {}\n", json_path);
      return 2;
    }
  }
  return t.failed > 0 ? 1 : 0;
}
