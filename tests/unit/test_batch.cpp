// isoquad batch: one output per input, failures and crashes isolated, the summary table, and
// --resume after a finished or an interrupted run.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "cli_run.hpp"
#include "corpus.hpp"

namespace {

namespace fs = std::filesystem;
using isoquad::test::CliRun;

const std::string kCli = ISOQUAD_CLI_PATH;
const fs::path kData = fs::path(ISOQUAD_SOURCE_DIR) / "data";

CliRun run(const std::string& args) { return isoquad::test::shell(kCli + " " + args); }

// A fresh folder for one test.
fs::path scratch() {
  const fs::path dir =
      fs::temp_directory_path() / ("isoquad_batch_" + std::to_string(::getpid()) + "_" +
                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::remove_all(dir);
  fs::create_directories(dir / "in");
  return dir;
}

fs::path broken_mesh(const fs::path& dir) {
  const fs::path p = dir / "in" / "broken.off";
  std::ofstream(p) << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n";
  return p;
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::map<std::string, nlohmann::json> rows_by_file(const nlohmann::json& summary) {
  std::map<std::string, nlohmann::json> rows;
  for (const auto& r : summary["rows"]) rows[fs::path(r["file"].get<std::string>()).stem()] = r;
  return rows;
}

}  // namespace

// Files, a quoted pattern and a corpus mesh, one of them broken, two at a time: an output per
// good file, the same as `isoquad remesh` writes, a failure row for the broken one with its
// code, exit status 1, and the summary as CSV, JSON and (--json) on stdout.
TEST(Batch, RemeshesEachFileAndIsolatesTheBrokenOne) {
  ISOQUAD_CORPUS_MESH(cylinder, "cylinder.off");
  const fs::path dir = scratch();
  fs::copy_file(kData / "sphere.off", dir / "in" / "sphere.off");
  broken_mesh(dir);
  const fs::path out = dir / "out";
  const CliRun r =
      run("batch '" + (dir / "in" / "*.off").string() + "' " + (kData / "fandisk.off").string() +
          " " + cylinder.string() + " -o " + out.string() + " --jobs 2 --quads 400 --json");
  EXPECT_EQ(r.status, 1) << r.err;
  const nlohmann::json summary = nlohmann::json::parse(r.out);
  EXPECT_EQ(summary, read_json(out / "summary.json"));
  EXPECT_EQ(summary["files"], 4);
  EXPECT_EQ(summary["ok"], 3);
  EXPECT_EQ(summary["failed"], 1);
  auto rows = rows_by_file(summary);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows["broken"]["status"], "failed");
  EXPECT_EQ(rows["broken"]["error_code"], "E012");
  EXPECT_EQ(rows["broken"]["exit_status"], 2);
  EXPECT_FALSE(fs::exists(out / "broken.obj"));
  EXPECT_TRUE(fs::exists(out / ".isoquad-batch" / "broken.log"));  // kept for a failed file
  for (const char* name : {"sphere", "fandisk", "cylinder"}) {
    const nlohmann::json& row = rows[name];
    EXPECT_EQ(row["status"], "ok") << name << row.dump();
    EXPECT_GT(row["quads"].get<int>(), 300) << name;
    EXPECT_EQ(row["folded"], 0) << name;
    EXPECT_LT(row["hausdorff"].get<double>(), 0.02) << name;
    EXPECT_TRUE(fs::exists(out / (std::string(name) + ".obj"))) << name;
  }
  // The header and one line per file.
  const std::string csv = slurp(out / "summary.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "file,output,status,exit_status,error_code,error,quads,irregular,scaled_jacobian_min,"
            "scaled_jacobian_mean,folded,hausdorff,mean_distance,seconds");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5);
  EXPECT_NE(r.err.find("4/4 done, 1 failed"), std::string::npos) << r.err;
  // Each file as `isoquad remesh` remeshes it, byte for byte.
  const CliRun one = run("remesh " + (kData / "fandisk.off").string() + " -o " +
                         (dir / "fandisk.obj").string() + " --quads 400 -q");
  ASSERT_EQ(one.status, 0) << one.err;
  EXPECT_EQ(slurp(dir / "fandisk.obj"), slurp(out / "fandisk.obj"));
  fs::remove_all(dir);
}

// --resume skips the inputs whose output exists, keeps their earlier rows and redoes the others.
TEST(Batch, ResumeRedoesOnlyTheMissingOutputs) {
  const fs::path dir = scratch();
  const fs::path out = dir / "out";
  const std::string inputs = (kData / "sphere.off").string() + " " +
                             (kData / "fandisk.off").string() + " " +
                             (kData / "nefertiti.off").string();
  const CliRun first = run("batch " + inputs + " -o " + out.string() + " --quads 300 -q");
  ASSERT_EQ(first.status, 0) << first.err;
  const auto before = rows_by_file(read_json(out / "summary.json"));
  fs::remove(out / "fandisk.obj");
  const auto old = fs::file_time_type::clock::now() - std::chrono::hours(1);
  fs::last_write_time(out / "sphere.obj", old);
  fs::last_write_time(out / "nefertiti.obj", old);
  const CliRun again = run("batch " + inputs + " -o " + out.string() + " --quads 300 --resume");
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_NE(again.err.find("2 of 3 files done before"), std::string::npos) << again.err;
  EXPECT_EQ(fs::last_write_time(out / "sphere.obj"), old);
  EXPECT_EQ(fs::last_write_time(out / "nefertiti.obj"), old);
  EXPECT_TRUE(fs::exists(out / "fandisk.obj"));
  const auto after = rows_by_file(read_json(out / "summary.json"));
  ASSERT_EQ(after.size(), 3u);
  EXPECT_EQ(after.at("sphere"), before.at("sphere"));
  EXPECT_EQ(after.at("fandisk")["status"], "ok");
  EXPECT_EQ(after.at("fandisk")["quads"], before.at("fandisk")["quads"]);
  fs::remove_all(dir);
}

// A batch killed with the file it was remeshing (as Ctrl-C kills both): --resume redoes the
// files without an output and leaves the finished one alone.
TEST(Batch, AnInterruptedRunResumes) {
  const fs::path dir = scratch();
  const fs::path out = dir / "out";
  const std::string inputs = (kData / "sphere.off").string() + " " +
                             (kData / "fandisk.off").string() + " " +
                             (kData / "nefertiti.off").string();
  // setsid: the batch leads a process group of its own, which the kill takes down whole.
  const CliRun killed =
      isoquad::test::shell("setsid " + kCli + " batch " + inputs + " -o " + out.string() +
                           " --jobs 1 -q & pid=$!; while [ ! -f " + (out / "sphere.obj").string() +
                           " ]; do sleep 0.02; done; kill -9 -$pid; wait $pid; echo $?");
  EXPECT_EQ(killed.out, "137\n") << killed.err;
  ASSERT_TRUE(fs::exists(out / "sphere.obj"));
  ASSERT_FALSE(fs::exists(out / "nefertiti.obj"));
  const auto finished = fs::last_write_time(out / "sphere.obj");
  const CliRun resumed = run("batch " + inputs + " -o " + out.string() + " --jobs 1 --resume");
  ASSERT_EQ(resumed.status, 0) << resumed.err;
  EXPECT_NE(resumed.err.find("1 of 3 files done before"), std::string::npos) << resumed.err;
  EXPECT_EQ(fs::last_write_time(out / "sphere.obj"), finished);
  for (const char* name : {"fandisk", "nefertiti"})
    EXPECT_TRUE(fs::exists(out / (std::string(name) + ".obj"))) << name;
  const auto rows = rows_by_file(read_json(out / "summary.json"));
  EXPECT_EQ(rows.at("fandisk")["status"], "ok");
  EXPECT_EQ(rows.at("nefertiti")["status"], "ok");
  // The first file's row was written unless the kill came between its output and its row.
  EXPECT_TRUE(rows.at("sphere")["status"] == "ok" || rows.at("sphere")["status"] == "resumed");
  fs::remove_all(dir);
}

// A file whose process dies (here of a SIGKILL, as the kernel's out-of-memory killer sends; a
// SIGSEGV would be caught by the sanitizers' handler, which exits instead) is a "crashed" row;
// the batch goes on with the others.
TEST(Batch, ACrashIsARowAndTheOthersGoOn) {
  const fs::path dir = scratch();
  const fs::path out = dir / "out";
  const pid_t batch = ::fork();
  ASSERT_GE(batch, 0);
  if (batch == 0) {
    const std::string fandisk = (kData / "fandisk.off").string(),
                      sphere = (kData / "sphere.off").string(), o = out.string();
    ::execl(kCli.c_str(), kCli.c_str(), "batch", fandisk.c_str(), sphere.c_str(), "-o", o.c_str(),
            "--jobs", "1", "-q", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // The batch's first child is fandisk's process (default size: seconds of work).
  pid_t child = 0;
  for (int tries = 0; tries < 2000 && child == 0; ++tries) {
    for (const auto& e : fs::directory_iterator("/proc")) {
      std::ifstream stat(e.path() / "stat");
      std::string pid, comm, state;
      long ppid = 0;
      if (stat >> pid >> comm >> state >> ppid && ppid == batch) child = std::stoi(pid);
    }
    if (child == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_NE(child, 0) << "the batch started no process";
  ::kill(child, SIGKILL);
  int status = 0;
  ASSERT_EQ(::waitpid(batch, &status, 0), batch);
  EXPECT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  const auto rows = rows_by_file(read_json(out / "summary.json"));
  EXPECT_EQ(rows.at("fandisk")["status"], "crashed");
  EXPECT_EQ(rows.at("fandisk")["exit_status"], 128 + SIGKILL);
  EXPECT_NE(rows.at("fandisk")["error"].get<std::string>().find("signal 9"), std::string::npos);
  EXPECT_EQ(rows.at("sphere")["status"], "ok");
  EXPECT_TRUE(fs::exists(out / "sphere.obj"));
  fs::remove_all(dir);
}

// The long options (--word or --two-words) a --help text names.
std::set<std::string> long_options(const std::string& help) {
  std::set<std::string> names;
  for (std::size_t at = help.find("--"); at != std::string::npos; at = help.find("--", at + 2)) {
    std::size_t end = at + 2;
    while (end < help.size() && (std::islower(help[end]) || help[end] == '-')) ++end;
    if (end > at + 2) names.insert(help.substr(at, end - at));
  }
  return names;
}

// Every option of remesh is an option of batch.
TEST(Batch, TakesEveryRemeshOption) {
  const CliRun remesh = run("remesh --help"), batch = run("batch --help");
  ASSERT_EQ(remesh.status, 0);
  ASSERT_EQ(batch.status, 0);
  const std::set<std::string> ours = long_options(batch.out), theirs = long_options(remesh.out);
  EXPECT_GT(theirs.size(), 25u);
  for (const std::string& name : theirs) EXPECT_EQ(ours.count(name), 1u) << name;
}

// What cannot be done is refused before any work (status 2): two inputs that would write the
// same output, a pattern that matches nothing, a folder without meshes.
TEST(Batch, RefusesWhatItCannotDoBeforeAnyWork) {
  const fs::path dir = scratch();
  fs::create_directories(dir / "a");
  fs::copy_file(kData / "sphere.off", dir / "a" / "sphere.off");
  const CliRun same = run("batch " + (kData / "sphere.off").string() + " " +
                          (dir / "a" / "sphere.off").string() + " -o " + (dir / "out").string());
  EXPECT_EQ(same.status, 2);
  EXPECT_NE(same.err.find("[E003]"), std::string::npos) << same.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
  const CliRun none = run("batch '" + (dir / "*.stl").string() + "' -o " + (dir / "out").string());
  EXPECT_EQ(none.status, 2);
  EXPECT_NE(none.err.find("no file matches"), std::string::npos) << none.err;
  const CliRun empty = run("batch " + (dir / "in").string() + " -o " + (dir / "out").string());
  EXPECT_EQ(empty.status, 2);
  EXPECT_NE(empty.err.find("holds no mesh file"), std::string::npos) << empty.err;
  fs::remove_all(dir);
}
