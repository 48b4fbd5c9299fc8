// isoquad batch IN... -o OUT_DIR: remeshes many files as `isoquad remesh` would, each in a
// process of its own, so that a failure or a crash in one file never stops the others; shows
// how far it is on stderr and writes a summary table (CSV and JSON) as each file ends, so that an
// interrupted run can be resumed (--resume).
#include <fcntl.h>
#include <fmt/format.h>
#include <fnmatch.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "commands.hpp"
#include "io/write_mesh.hpp"
#include "isoquad/error.hpp"
#include "progress_bar.hpp"
#include "remesh_args.hpp"

extern char** environ;

namespace isoquad::cli {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

struct BatchArgs {
  std::vector<std::string> inputs;
  std::string out_dir, format = "obj", report_dir, summary;
  uint32_t jobs = 1;
  bool resume = false, json = false, quiet = false;
  // The child's side (hidden): the one file it remeshes and the file it writes its row to.
  std::string one, row;
  RemeshArgs remesh;
};

// The summary's columns, in order (CSV header, JSON keys).
const std::vector<std::string> kColumns = {"file",
                                           "output",
                                           "status",
                                           "exit_status",
                                           "error_code",
                                           "error",
                                           "quads",
                                           "irregular",
                                           "scaled_jacobian_min",
                                           "scaled_jacobian_mean",
                                           "folded",
                                           "hausdorff",
                                           "mean_distance",
                                           "seconds"};

bool is_mesh_file(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".obj" || ext == ".off" || ext == ".ply" || ext == ".stl";
}

std::vector<fs::path> sorted_files(const fs::path& folder,
                                   const std::function<bool(const fs::path&)>& keep) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(folder, ec))
    if (e.is_regular_file(ec) && keep(e.path())) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

// Files as given; a folder's mesh files (.obj, .off, .ply, .stl, not in subfolders); a pattern
// with * ? or [ in its last part (quoted from the shell), the files of its folder it matches.
// In the order given, each file once. A named file that does not exist fails at its turn.
// \throw Error(invalid_input, E001) a folder without mesh files or a pattern matching none.
std::vector<fs::path> expand_inputs(const std::vector<std::string>& inputs) {
  std::vector<fs::path> files;
  for (const std::string& in : inputs) {
    const fs::path p(in);
    const std::string name = p.filename().string();
    std::error_code ec;
    if (name.find_first_of("*?[") != std::string::npos) {
      const fs::path folder = p.has_parent_path() ? p.parent_path() : fs::path(".");
      const auto found = sorted_files(folder, [&](const fs::path& f) {
        return ::fnmatch(name.c_str(), f.filename().c_str(), FNM_PERIOD) == 0;
      });
      if (found.empty())
        throw Error(ErrorKind::invalid_input, "E001", fmt::format("no file matches {}", in));
      files.insert(files.end(), found.begin(), found.end());
    } else if (fs::is_directory(p, ec)) {
      const auto found = sorted_files(p, is_mesh_file);
      if (found.empty())
        throw Error(ErrorKind::invalid_input, "E001",
                    fmt::format("the folder {} holds no mesh file (.obj, .off, .ply, .stl)", in));
      files.insert(files.end(), found.begin(), found.end());
    } else {
      files.push_back(p);
    }
  }
  std::set<fs::path> seen;
  std::vector<fs::path> once;
  for (const fs::path& f : files)
    if (seen.insert(fs::absolute(f).lexically_normal()).second) once.push_back(f);
  return once;
}

// OUT_DIR/<name>.<format>, one per input.
// \throw Error(invalid_input, E003) when two inputs would write the same output.
std::vector<fs::path> output_paths(const std::vector<fs::path>& files, const BatchArgs& a) {
  std::vector<fs::path> outputs;
  std::map<fs::path, fs::path> writer;
  for (const fs::path& f : files) {
    outputs.push_back(fs::path(a.out_dir) / (f.stem().string() + "." + a.format));
    const auto [at, fresh] = writer.emplace(outputs.back(), f);
    if (!fresh)
      throw Error(ErrorKind::invalid_input, "E003",
                  fmt::format("{} and {} would both be written to {}: give them separate runs",
                              at->second.string(), f.string(), outputs.back().string()));
  }
  return outputs;
}

Json empty_row(const fs::path& file, const fs::path& output) {
  Json row;
  for (const std::string& c : kColumns) row[c] = nullptr;
  row["file"] = file.string();
  row["output"] = output.string();
  return row;
}

// The figures of a run's JSON report (with its quality measurements) that the summary shows.
void fill_from_report(Json& row, const std::string& report) {
  const nlohmann::json r = nlohmann::json::parse(report);
  row["quads"] = r.at("quads");
  const nlohmann::json& q = r.at("quality");
  row["irregular"] = q.at("irregular_vertices");
  row["scaled_jacobian_min"] = q.at("scaled_jacobian").at("min");
  row["scaled_jacobian_mean"] = q.at("scaled_jacobian").at("mean");
  row["folded"] = q.at("scaled_jacobian_surface").at("nonpositive");
  row["hausdorff"] = q.at("hausdorff");
  row["mean_distance"] = q.at("mean_distance");
}

// The child: remeshes one file as `isoquad remesh` would, the lines it says on stderr (the
// batch's log for the file; no stage bar or stage lines: the batch shows its own bar over the
// files), and writes its row.
int run_one(BatchArgs a) {
  const auto t0 = Clock::now();
  const fs::path file = a.one;
  const fs::path output = fs::path(a.out_dir) / (file.stem().string() + "." + a.format);
  // The jobs share the cores (the output is the same for any thread count).
  if (a.remesh.threads == 0 && a.jobs > 1)
    a.remesh.threads = std::max(1u, std::thread::hardware_concurrency() / a.jobs);
  Json row = empty_row(file, output);
  int status = 0;
  try {
    const std::string report_dir =
        a.report_dir.empty() ? "" : (fs::path(a.report_dir) / file.stem()).string();
    fill_from_report(row, remesh_file(a.remesh, file.string(), output.string(), report_dir, true,
                                      [](const std::string& s) { fmt::print(stderr, "{}\n", s); }));
    row["status"] = "ok";
  } catch (const Error& e) {
    status = e.exit_status();
    row["error_code"] = e.code();
    row["error"] = e.what();
  } catch (const std::exception& e) {
    status = static_cast<int>(ErrorKind::internal);
    row["error_code"] = "E700";
    row["error"] = e.what();
  }
  if (status != 0) row["status"] = "failed";
  row["exit_status"] = status;
  row["seconds"] = std::chrono::duration<double>(Clock::now() - t0).count();
  write_file_atomically(a.row, [&](std::ostream& out) { out << row.dump(2) << '\n'; });
  return status;
}

std::string csv_field(const Json& v) {
  if (v.is_null()) return "";
  std::string s = v.is_string() ? v.get<std::string>() : v.dump();
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string quoted = "\"";
  for (const char c : s) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

Json summary_json(const std::vector<Json>& rows, double seconds) {
  uint32_t ok = 0, failed = 0;
  Json list = Json::array();
  for (const Json& r : rows)
    if (!r["status"].is_null()) {
      list.push_back(r);
      (r["status"] == "failed" || r["status"] == "crashed" ? failed : ok) += 1;
    }
  return {
      {"files", rows.size()}, {"ok", ok}, {"failed", failed}, {"seconds", seconds}, {"rows", list}};
}

void write_summary(const fs::path& stem, const Json& summary) {
  write_file_atomically(fs::path(stem.string() + ".json"),
                        [&](std::ostream& out) { out << summary.dump(2) << '\n'; });
  write_file_atomically(fs::path(stem.string() + ".csv"), [&](std::ostream& out) {
    for (std::size_t c = 0; c < kColumns.size(); ++c) out << (c ? "," : "") << kColumns[c];
    out << '\n';
    for (const Json& r : summary["rows"]) {
      for (std::size_t c = 0; c < kColumns.size(); ++c)
        out << (c ? "," : "") << csv_field(r[kColumns[c]]);
      out << '\n';
    }
  });
}

// The rows of an earlier run's summary, by file (for --resume).
std::map<std::string, Json> earlier_rows(const fs::path& stem) {
  std::map<std::string, Json> rows;
  std::ifstream in(stem.string() + ".json");
  if (!in) return rows;
  try {
    const Json j = Json::parse(in);
    for (const Json& r : j.at("rows")) rows[r.at("file").get<std::string>()] = r;
  } catch (const std::exception&) {
    // An unreadable summary only loses the earlier figures: the outputs decide what is done.
  }
  return rows;
}

// Runs `argv` with stdout to /dev/null and stderr to `log`; returns its process id.
pid_t spawn(const std::vector<std::string>& argv, const fs::path& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<char*> args;
  for (const std::string& s : argv) args.push_back(const_cast<char*>(s.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int err = posix_spawn(&pid, "/proc/self/exe", &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (err != 0)
    throw Error(ErrorKind::internal, "E700",
                fmt::format("cannot start a process for {}: {}", argv.back(), std::strerror(err)));
  return pid;
}

// One row per file, and the files to remesh: with --resume, those without an output (an
// existing output keeps its earlier row, or is "resumed" when that is lost).
struct Plan {
  std::vector<Json> rows;
  std::vector<std::size_t> todo;
};

Plan plan(const std::vector<fs::path>& files, const std::vector<fs::path>& outputs, bool resume,
          const fs::path& stem) {
  Plan p;
  const std::map<std::string, Json> earlier = resume ? earlier_rows(stem) : decltype(earlier){};
  for (std::size_t i = 0; i < files.size(); ++i) {
    p.rows.push_back(empty_row(files[i], outputs[i]));
    if (!resume || !fs::exists(outputs[i])) {
      p.todo.push_back(i);
      continue;
    }
    const auto e = earlier.find(files[i].string());
    if (e != earlier.end() && e->second["status"] == "ok")
      p.rows.back() = e->second;
    else
      p.rows.back()["status"] = "resumed";
  }
  return p;
}

// How far the batch is, on stderr: a bar redrawn in place on a terminal, else a line per file.
class ProgressLine {
 public:
  ProgressLine(std::size_t files, std::size_t to_run, bool quiet)
      : t0_(Clock::now()),
        files_(files),
        to_run_(to_run),
        quiet_(quiet),
        tty_(stderr_is_terminal()) {}

  double seconds() const { return std::chrono::duration<double>(Clock::now() - t0_).count(); }

  // A file ended (ok or not), with the line that says so.
  void ended(bool ok, const std::string& line) {
    ++done_;
    failed_ += ok ? 0 : 1;
    show(line);
  }

  void show(const std::string& line) const {
    if (quiet_) return;
    const double elapsed = seconds();
    const std::size_t left = to_run_ - done_, finished = files_ - left;
    const std::string eta =
        done_ > 0 && left > 0
            ? fmt::format(", about {} left", clock_time(elapsed / double(done_) * double(left)))
            : "";
    const std::string counts = fmt::format("{}/{} done, {} failed, {} elapsed{}", finished, files_,
                                           failed_, clock_time(elapsed), eta);
    if (tty_) {
      fmt::print(stderr, "\r\033[K{}{}{} {}", line, line.empty() ? "" : "\n",
                 bar_cells(double(finished) / double(std::max<std::size_t>(files_, 1))), counts);
    } else if (!line.empty()) {
      fmt::print(stderr, "batch: {} ({})\n", line, counts);
    }
  }

  void close() const {
    if (tty_ && !quiet_) fmt::print(stderr, "\n");
  }
  std::size_t failed() const { return failed_; }

 private:
  Clock::time_point t0_;
  std::size_t files_, to_run_, done_ = 0, failed_ = 0;
  bool quiet_, tty_;
};

// The row a file's process left, or, when it left none (killed by a signal, or ended without
// writing it), a "crashed" row.
Json ended_row(Json row, const fs::path& row_path, const fs::path& log, int wstatus) {
  std::ifstream in(row_path);
  const Json written = in ? Json::parse(in, nullptr, false) : Json();
  if (written.is_object() && !written["status"].is_null()) return written;
  row["status"] = "crashed";
  row["exit_status"] = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : 128 + WTERMSIG(wstatus);
  row["error_code"] = "E700";
  row["error"] = WIFSIGNALED(wstatus)
                     ? fmt::format("killed by signal {} ({}); its output: {}", WTERMSIG(wstatus),
                                   strsignal(WTERMSIG(wstatus)), log.string())
                     : fmt::format("ended without a result; its output: {}", log.string());
  return row;
}

int run_batch(const BatchArgs& a) {
  const std::vector<fs::path> files = expand_inputs(a.inputs);
  const std::vector<fs::path> outputs = output_paths(files, a);
  check_output_folder(a.out_dir);
  if (!a.report_dir.empty()) check_output_folder(a.report_dir);
  const fs::path stem = a.summary.empty() ? fs::path(a.out_dir) / "summary" : fs::path(a.summary);
  const fs::path work = fs::path(a.out_dir) / ".isoquad-batch";
  fs::create_directories(work);
  if (stem.has_parent_path()) fs::create_directories(stem.parent_path());
  Plan p = plan(files, outputs, a.resume, stem);
  ProgressLine progress(files.size(), p.todo.size(), a.quiet);
  if (p.todo.size() < files.size() && !a.quiet)
    fmt::print(stderr, "batch: {} of {} files done before (--resume)\n",
               files.size() - p.todo.size(), files.size());
  progress.show("");
  const auto row_path = [&](std::size_t i) { return work / fmt::format("{}.json", i); };
  const auto log_path = [&](std::size_t i) { return work / (files[i].stem().string() + ".log"); };
  std::map<pid_t, std::size_t> running;
  std::size_t next = 0;
  while (next < p.todo.size() || !running.empty()) {
    while (next < p.todo.size() && running.size() < a.jobs) {
      const std::size_t i = p.todo[next++];
      std::vector<std::string> argv = command_line();
      argv.insert(argv.end(), {"--row", row_path(i).string(), "--one", files[i].string()});
      std::error_code ec;
      fs::remove(row_path(i), ec);
      running[spawn(argv, log_path(i))] = i;
    }
    int wstatus = 0;
    const pid_t pid = ::waitpid(-1, &wstatus, 0);
    if (pid < 0 && errno == EINTR) continue;
    if (pid < 0) throw Error(ErrorKind::internal, "E700", "lost track of the file processes");
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const std::size_t i = it->second;
    running.erase(it);
    Json& row = p.rows[i];
    row = ended_row(row, row_path(i), log_path(i), wstatus);
    const bool ok = row["status"] == "ok";
    std::error_code ec;
    fs::remove(row_path(i), ec);
    if (ok) fs::remove(log_path(i), ec);  // a failed file's messages stay beside the outputs
    progress.ended(
        ok, ok ? fmt::format("{}: {} quads, {:.1f} s", files[i].string(), row["quads"].dump(),
                             row["seconds"].get<double>())
               : fmt::format("{}: {}: {}", files[i].string(), row["status"].get<std::string>(),
                             row["error"].get<std::string>()));
    write_summary(stem, summary_json(p.rows, progress.seconds()));
  }
  const Json summary = summary_json(p.rows, progress.seconds());
  write_summary(stem, summary);
  std::error_code ec;
  fs::remove(work, ec);  // only when empty: the logs of failed files keep it
  progress.close();
  if (!a.quiet)
    fmt::print(stderr, "batch: {} of {} files remeshed, {} failed; summary in {}.csv and .json\n",
               summary["ok"].get<uint32_t>(), files.size(), progress.failed(), stem.string());
  if (a.json) std::cout << summary.dump(2) << '\n';
  return progress.failed() > 0 ? 1 : 0;
}

}  // namespace

Runner add_batch(CLI::App& app) {
  auto a = std::make_shared<BatchArgs>();
  CLI::App* sub = app.add_subcommand(
      "batch",
      "Remesh many files, each as `isoquad remesh` would, in processes of their own; a summary "
      "table (CSV and JSON) in the output folder");
  sub->add_option("inputs", a->inputs,
                  "Input meshes: files, folders (their .obj, .off, .ply and .stl files) or "
                  "quoted patterns such as 'meshes/*.off'")
      ->required();
  sub->add_option("-o,--output", a->out_dir, "Output folder (created if missing)")->required();
  sub->add_option("--format", a->format, "Output format: obj, off or ply")
      ->check(CLI::IsMember({"obj", "off", "ply"}))
      ->capture_default_str();
  sub->add_option("-j,--jobs", a->jobs,
                  "Files remeshed at once, each in its own process (the cores are shared out "
                  "between them unless --threads is given)")
      ->check(CLI::Range(1u, 1024u))
      ->capture_default_str();
  sub->add_flag("--resume", a->resume,
                "Skip the inputs whose output exists (outputs are written atomically, so an "
                "existing one is complete), keeping their rows of the earlier summary");
  sub->add_option("--summary", a->summary,
                  "Path of the summary table without its extension (default OUT_DIR/summary: "
                  "OUT_DIR/summary.csv and OUT_DIR/summary.json)");
  sub->add_option("--report", a->report_dir,
                  "Write each file's report (as remesh --report) into a folder of this one named "
                  "after the file");
  sub->add_flag("--json", a->json, "Print the summary as JSON on stdout at the end");
  sub->add_flag("-q,--quiet", a->quiet, "No progress on stderr");
  sub->add_option("--one", a->one)->group("");
  sub->add_option("--row", a->row)->group("");
  add_remesh_options(*sub, a->remesh);
  return [a] { return a->one.empty() ? run_batch(*a) : run_one(*a); };
}

}  // namespace isoquad::cli
