// The generated stress set (stress_shapes.hpp) outside the tests:
//
//   stress_shapes list                  each case: family, triangles, Euler characteristic, params
//   stress_shapes dump DIR [--diagonal D]...   every mesh as DIR/NAME.obj (NAME_dD.obj when
//                                       scaled), to look at or to give to `isoquad remesh`
//   stress_shapes run --csv FILE [--segmentation vsa|field] [--quads Q]... [--diagonal D]...
//                     [--ci] [--only NAME]... [--shard I/N] [--threads T] [--timeout S]
//       remeshes every case at every size and diagonal, each in a process of its own, and appends
//       one row per run to FILE (read first: the runs it has are skipped, so an interrupted run
//       goes on where it stopped); the shapes go in turn through the families.
//
// The rows: status (ok, the error code, crash, or timeout), quads, the validity of issue 32 (pure
// quad, manifold, oriented, the input's topology, no quad with scaled Jacobian <= 0.001 against its
// own normal, at a count within 10%), the scaled Jacobian (mean, min), quads at most 0.001, quads
// folded against the surface, the share of quads of aspect above 2, the output's diagonal over
// the input's, the seconds of the remesh and which layout the components got (field, or vsa where
// the field's fell back). scripts/stress-table summarizes them.
#include <fmt/format.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "io/write_mesh.hpp"
#include "isoquad/error.hpp"
#include "metrics/quality.hpp"
#include "pipeline/remesh.hpp"
#include "stress_shapes.hpp"

using namespace isoquad;
using isoquad::test::StressCase;

namespace {

double diagonal_of(const PolyMesh& m) {
  Box3 box;
  for (const Vec3& p : m.positions) box.add(p);
  return box.diagonal();
}

const char* kHeader =
    "name,family,segmentation,quads_asked,diagonal,status,quads,valid,count_ok,sj_mean,sj_min,"
    "sj_invalid,folded,aspect_above_2,scale_ratio,seconds,layout";

// One run's row (without its key columns).
std::string run_one(const StressCase& c, const std::string& segmentation, double quads,
                    double diagonal, uint32_t threads) {
  const PolyMesh input = test::scaled_to_diagonal(test::build_stress_mesh(c), diagonal);
  RemeshOptions o;
  o.quads = quads;
  o.segmentation = segmentation;
  o.threads = threads;
  o.quality = false;
  const auto start = std::chrono::steady_clock::now();
  RemeshRun run;
  try {
    run = remesh_run(input, o);
  } catch (const Error& e) {
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return fmt::format("{},,,,,,,,,,{:.1f}", e.code(), s);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const PolyMesh& q = run.result.quads;
  const QualityReport r = measure_quality(q, &input);
  const bool valid = r.pure_quad && r.edge_manifold && r.vertex_manifold && r.oriented &&
                     r.same_topology && r.sj_invalid == 0;
  const bool count_ok = quads == 0 || std::fabs(double(q.num_faces()) - quads) <= 0.1 * quads;
  // Which segmentation laid out the components: a field layout can fall back to VSA.
  const nlohmann::json report = nlohmann::json::parse(run.result.report);
  std::set<std::string> sources;
  for (const auto& comp : report.at("components"))
    sources.insert(comp.value("layout_source", "vsa"));
  return fmt::format("ok,{},{},{},{:.4f},{:.4f},{},{},{:.2f},{:.4f},{:.1f},{}", q.num_faces(),
                     int(valid), int(count_ok), r.sj_mean, r.sj_min, r.sj_invalid,
                     r.sj_surface_nonpositive, r.aspect_above_2, diagonal_of(q) / diagonal, seconds,
                     sources.size() == 1 ? *sources.begin() : "mixed");
}

// run_one in a child process, so that a crash is a row ("crash") and a run past `timeout`
// seconds is killed ("timeout").
std::string run_apart(const StressCase& c, const std::string& segmentation, double quads,
                      double diagonal, uint32_t threads, double timeout) {
  int fd[2];
  if (pipe(fd) != 0) return "pipe,,,,,,,,,,";
  const pid_t child = fork();
  if (child == 0) {
    close(fd[0]);
    const std::string row = run_one(c, segmentation, quads, diagonal, threads);
    if (write(fd[1], row.data(), row.size()) < 0) _exit(1);
    _exit(0);
  }
  close(fd[1]);
  std::string row;
  pollfd p{fd[0], POLLIN, 0};
  const auto start = std::chrono::steady_clock::now();
  for (char buf[512];;) {
    const double left =
        timeout - std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (left <= 0) {
      kill(child, SIGKILL);
      row = fmt::format("timeout,,,,,,,,,,{:.0f}", timeout);
      break;
    }
    if (poll(&p, 1, int(std::min(left, 1e6) * 1000)) <= 0) continue;
    const ssize_t n = read(fd[0], buf, sizeof buf);
    if (n <= 0) break;
    row.append(buf, std::size_t(n));
  }
  close(fd[0]);
  int status = 0;
  waitpid(child, &status, 0);
  return row.empty() ? std::string("crash,,,,,,,,,,") : row;
}

int run(const std::string& csv, const std::string& segmentation, const std::vector<double>& sizes,
        const std::vector<double>& diagonals, const std::vector<const StressCase*>& cases,
        int shard, int shards, uint32_t threads, double timeout) {
  std::set<std::string> done;
  {
    std::ifstream in(csv);
    for (std::string line; std::getline(in, line);) {
      std::size_t cut = 0;
      for (int k = 0; k < 5 && cut != std::string::npos; ++k) cut = line.find(',', cut + 1);
      done.insert(line.substr(0, cut));
    }
  }
  const bool fresh = done.empty();
  std::ofstream out(csv, std::ios::app);
  if (fresh) out << kHeader << "\n" << std::flush;
  int job = 0;
  for (const StressCase* c : cases)
    for (double quads : sizes)
      for (double d : diagonals) {
        if (job++ % shards != shard) continue;
        const std::string key =
            fmt::format("{},{},{},{},{:g}", c->name, c->family, segmentation, quads, d);
        if (done.count(key)) continue;
        std::cerr << key << std::endl;
        out << key << "," << run_apart(*c, segmentation, quads, d, threads, timeout) << "\n"
            << std::flush;
      }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The generated stress set of issue 32"};
  app.require_subcommand(1);
  auto* list = app.add_subcommand("list", "List the cases");
  auto* dump = app.add_subcommand("dump", "Write every mesh as OBJ");
  std::string dir;
  std::vector<double> diagonals;
  dump->add_option("dir", dir)->required();
  dump->add_option("--diagonal", diagonals, "bounding-box diagonals (default: as built)");
  auto* runs = app.add_subcommand("run", "Remesh the cases, one CSV row per run");
  std::string csv, segmentation = "vsa", shard_arg = "0/1";
  std::vector<double> sizes;
  std::vector<std::string> only;
  bool ci = false;
  uint32_t threads = 0;
  double timeout = 600;
  runs->add_option("--csv", csv)->required();
  runs->add_option("--segmentation", segmentation);
  runs->add_option("--quads", sizes, "quad counts (0: the default size; default 1500 and 0)");
  runs->add_option("--diagonal", diagonals, "bounding-box diagonals (default 1e-3 and 1e3)");
  runs->add_flag("--ci", ci, "only the CI subset");
  runs->add_option("--only", only, "only these cases");
  runs->add_option("--shard", shard_arg, "I/N: every N-th run from the I-th");
  runs->add_option("--threads", threads);
  runs->add_option("--timeout", timeout, "seconds a run may take (default 600)");
  CLI11_PARSE(app, argc, argv);

  std::vector<const StressCase*> cases;
  if (ci) {
    cases = test::stress_ci_cases();
  } else {
    for (const StressCase& c : test::stress_cases())
      if (only.empty() || std::find(only.begin(), only.end(), c.name) != only.end())
        cases.push_back(&c);
  }
  if (list->parsed()) {
    for (const StressCase* c : cases) {
      const auto start = std::chrono::steady_clock::now();
      const PolyMesh m = test::build_stress_mesh(*c);
      fmt::print("{}\t{}\t{}\t{}\t{:.2f}s\t{}\n", c->name, m.num_faces(), c->euler,
                 c->boundary_loops,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                 c->params);
    }
    return 0;
  }
  if (dump->parsed()) {
    std::filesystem::create_directories(dir);
    for (const StressCase* c : cases) {
      const PolyMesh m = test::build_stress_mesh(*c);
      if (diagonals.empty()) write_mesh(std::filesystem::path(dir) / (c->name + ".obj"), m);
      for (double d : diagonals)
        write_mesh(std::filesystem::path(dir) / fmt::format("{}_d{:g}.obj", c->name, d),
                   test::scaled_to_diagonal(m, d));
    }
    return 0;
  }
  if (sizes.empty()) sizes = {1500, 0};
  if (diagonals.empty()) diagonals = {1e-3, 1e3};
  int shard = 0, shards = 1;
  if (std::sscanf(shard_arg.c_str(), "%d/%d", &shard, &shards) != 2 || shards < 1) return 2;
  // Family after family, one shape of each in turn: a run cut short covers every family.
  std::stable_sort(cases.begin(), cases.end(), [](const StressCase* a, const StressCase* b) {
    return a->name.substr(a->name.size() - 2) < b->name.substr(b->name.size() - 2);
  });
  return run(csv, segmentation, sizes, diagonals, cases, shard, shards, threads, timeout);
}
