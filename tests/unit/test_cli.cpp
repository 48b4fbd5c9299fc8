// The command line: exit statuses, messages on stderr, and --json output.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "cli_run.hpp"
#include "corpus.hpp"
#include "io/write_mesh.hpp"
#include "report_checks.hpp"
#include "shapes.hpp"

namespace {

using isoquad::test::CliRun;
using isoquad::test::shell;

CliRun run(const std::string& args) { return shell(std::string(ISOQUAD_CLI_PATH) + " " + args); }

std::filesystem::path write_temp(const std::string& name, const std::string& content) {
  const auto p = std::filesystem::temp_directory_path() / name;
  std::ofstream(p) << content;
  return p;
}

}  // namespace

TEST(Cli, VersionAndHelp) {
  EXPECT_EQ(run("--version").status, 0);
  const CliRun help = run("info --help");
  EXPECT_EQ(help.status, 0);
  EXPECT_NE(help.out.find("--repair"), std::string::npos);
  EXPECT_NE(run("").status, 0);  // a subcommand is required
}

TEST(Cli, InfoOnSampleMesh) {
  const CliRun r = run("info " + (isoquad::test::data_dir() / "elephant.off").string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("genus 3"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("would accept"), std::string::npos);
  const CliRun j = run("info --json " + (isoquad::test::data_dir() / "nefertiti.off").string());
  ASSERT_EQ(j.status, 0) << j.err;
  const auto doc = nlohmann::json::parse(j.out);
  EXPECT_EQ(doc["components"][0]["boundary_loops"], 1);
  EXPECT_EQ(doc["components"][0]["euler_characteristic"], 1);
  EXPECT_EQ(doc["remesh_would_accept"], true);
}

TEST(Cli, MalformedFileGivesLocatedErrorAndExitStatus2) {
  const auto p = write_temp("isoquad_cli_bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  const CliRun r = run("info " + p.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("isoquad: error:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("isoquad_cli_bad.obj:4:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("E012"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty());
  std::filesystem::remove(p);
  EXPECT_EQ(run("info /nonexistent/mesh.off").status, 2);
}

TEST(Cli, InfoExplainsWhatRemeshWouldReject) {
  // Three triangles on edge 1-2 (an edge with three faces), each big enough to be kept.
  std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 1 1 1\n";
  obj += "f 1 2 3\nf 2 1 4\nf 1 2 5\n";
  const auto p = write_temp("isoquad_cli_nm.obj", obj);
  const CliRun r = run("info " + p.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("reject E101"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("would reject"), std::string::npos);
  const CliRun fixed = run("info --repair " + p.string());
  EXPECT_EQ(fixed.status, 0) << fixed.out;
  EXPECT_NE(fixed.out.find("repair W101"), std::string::npos) << fixed.out;
  std::filesystem::remove(p);
}

// `info` runs remesh's own checks (check_input): what it rejects, remesh rejects with the same
// code, and remesh prepares with every input option info takes. A sphere with a vertex at 1e100
// (info accepted it, remesh aborted in CLP) is E103 for both; a plate with a slit whose sides
// are 1e-4 apart is welded by both with --weld-eps (remesh ignored the option).
TEST(Cli, InfoAcceptsOnlyWhatRemeshAccepts) {
  const auto dir = std::filesystem::temp_directory_path();
  const auto out = dir / "isoquad_cli_agree_quads.obj";
  isoquad::PolyMesh spike = isoquad::test::icosphere(2);
  spike.positions[7] = {1e100, 0, 0};
  const auto spiked = dir / "isoquad_cli_spike.off";
  isoquad::write_mesh(spiked, spike);
  const CliRun info = run("info " + spiked.string());
  EXPECT_EQ(info.status, 2) << info.out;
  EXPECT_NE(info.out.find("reject E103: component 0 has no area"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("would reject"), std::string::npos) << info.out;
  const CliRun remesh = run("remesh -q --quads 300 " + spiked.string() + " -o " + out.string());
  EXPECT_EQ(remesh.status, 2) << remesh.err;
  EXPECT_NE(remesh.err.find("[E103]"), std::string::npos) << remesh.err;

  // The slit: x = 0.5 from y = 0 to y = 0.5, its right side's vertices moved by 1e-4.
  const isoquad::PolyMesh grid = isoquad::test::grid_plate(8, 8);
  isoquad::PolyMesh slit;
  slit.positions = grid.positions;
  std::map<uint32_t, uint32_t> copy;
  for (uint32_t j = 0; j < 4; ++j) {
    copy[j * 9 + 4] = uint32_t(slit.positions.size());
    slit.positions.push_back(grid.positions[j * 9 + 4] + isoquad::Vec3{1e-4, 0, 0});
  }
  for (std::size_t f = 0; f < grid.num_faces(); ++f) {
    const uint32_t cell = uint32_t(f / 2), i = cell % 8, j = cell / 8;
    std::vector<uint32_t> vs(grid.face(f).begin(), grid.face(f).end());
    if (i >= 4 && j < 4)
      for (uint32_t& v : vs)
        if (copy.count(v)) v = copy[v];
    slit.add_face(vs);
  }
  const auto slitted = dir / "isoquad_cli_slit.off";
  isoquad::write_mesh(slitted, slit);
  const CliRun welded = run("info --weld-eps 0.001 " + slitted.string());
  EXPECT_EQ(welded.status, 0) << welded.out;
  EXPECT_NE(welded.out.find("repair W104: welded 4 coincident vertices"), std::string::npos)
      << welded.out;
  const CliRun remeshed =
      run("remesh --json --quads 100 --weld-eps 0.001 " + slitted.string() + " -o " + out.string());
  ASSERT_EQ(remeshed.status, 0) << remeshed.err;
  EXPECT_NE(remeshed.err.find("welded 4 coincident vertices [W104]"), std::string::npos)
      << remeshed.err;
  const auto doc = nlohmann::json::parse(remeshed.out);
  EXPECT_EQ(doc["options"]["weld_epsilon"], 0.001);
  const CliRun apart = run("info " + slitted.string());
  EXPECT_EQ(apart.out.find("W104"), std::string::npos) << apart.out;
  for (const auto& p : {spiked, slitted, out}) std::filesystem::remove(p);
}

TEST(Cli, FieldPrintsSingularitiesThatSumToEulerAndDrawsThem) {
  const auto png = std::filesystem::temp_directory_path() / "isoquad_cli_field.png";
  const CliRun r = run("field " + (isoquad::test::data_dir() / "elephant.off").string() +
                       " --quads 800 --json --png " + png.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_EQ(doc.size(), 1u);
  // Poincare-Hopf: the indices (k/4 at interior vertices; none on this closed surface's boundary)
  // sum to the Euler characteristic, -4 for the genus-3 elephant.
  int64_t quarters = 0;
  for (const auto& [index, count] : doc[0]["interior_singularities"].items())
    quarters += std::stoll(index.substr(0, index.find('/'))) * count.get<int64_t>();
  EXPECT_EQ(quarters, 4 * -4);
  EXPECT_EQ(doc[0]["boundary_singularities"], 0);
  EXPECT_GT(doc[0]["solves"].get<int>(), 0);
  std::ifstream in(png, std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  EXPECT_EQ(std::string(sig + 1, 3), "PNG");
  std::filesystem::remove(png);
}

// Coordinates at 1e300 and 1e-300 (remesh crashed from about 1e154 while info said "diagonal
// inf, area -nan ... would accept"): info gives a finite diagonal and accepts, and remesh
// writes quads; both exit 0.
TEST(Cli, InfoAndRemeshAgreeAtExtremeScales) {
  for (const double scale : {1e300, 1e-300}) {
    isoquad::PolyMesh m = isoquad::test::icosphere(3);
    for (isoquad::Vec3& p : m.positions) p = scale * p;
    const auto in = std::filesystem::temp_directory_path() / "isoquad_cli_scaled.off";
    const auto out = std::filesystem::temp_directory_path() / "isoquad_cli_scaled_quads.obj";
    isoquad::write_mesh(in, m);
    std::filesystem::remove(out);
    const CliRun info = run("info --json " + in.string());
    ASSERT_EQ(info.status, 0) << scale << info.err;
    const auto doc = nlohmann::json::parse(info.out);
    EXPECT_EQ(doc["remesh_would_accept"], true) << scale;
    ASSERT_TRUE(doc["bounding_box"]["diagonal"].is_number()) << scale << info.out;
    EXPECT_NEAR(doc["bounding_box"]["diagonal"].get<double>() / scale, 2 * std::sqrt(3.0), 0.1);
    const CliRun remesh = run("remesh -q --quads 300 " + in.string() + " -o " + out.string());
    EXPECT_EQ(remesh.status, 0) << scale << remesh.err;
    EXPECT_TRUE(std::filesystem::exists(out)) << scale;
    std::filesystem::remove(in);
    std::filesystem::remove(out);
  }
}

// Option values out of range were read as the default (--quads 0 and --quads -5 ran at the
// default size): each is refused, naming the option and the value, with the status of invalid
// input and no output; so is every other refused command line (CLI11's statuses were 104-109).
TEST(Cli, OptionValuesOutOfRangeAreRefused) {
  const std::string sphere = (isoquad::test::data_dir() / "sphere.off").string();
  const auto out = std::filesystem::temp_directory_path() / "isoquad_cli_refused.obj";
  std::filesystem::remove(out);
  const std::vector<std::pair<std::string, std::string>> cases{
      {"--quads 0", "--quads: 0 is not a quad count"},
      {"--quads -5", "--quads: -5 is not a quad count"},
      {"--quads many", "--quads: many is not a number"},
      {"--edge-length -1", "--edge-length: -1 is not a positive length"},
      {"--edge-length 0", "--edge-length: 0 is not a positive length"},
      {"--edge-length inf", "--edge-length: inf is not a positive length"},
      {"--patches 0", "--patches: a patch count must be positive"},
      {"--feature-angle 181", "--feature-angle: 181 is not an angle in [0, 180]"},
      {"--feature-angle -1", "--feature-angle: -1 is not an angle"},
      {"--weld-eps 0.5", "--weld-eps: 0.5 is not a fraction"},
      {"--threads -1", "--threads: -1 is not a thread count"},
      {"--quads 500 --edge-length 0.1", "--edge-length excludes --quads"}};
  for (const auto& [option, message] : cases) {
    const CliRun r = run("remesh " + sphere + " -o " + out.string() + " -q " + option);
    EXPECT_EQ(r.status, 2) << option << ": " << r.err;
    EXPECT_NE(r.err.find("isoquad: error: " + message), std::string::npos) << option << r.err;
    EXPECT_TRUE(r.out.empty()) << option;
    EXPECT_FALSE(std::filesystem::exists(out)) << option;
  }
  const CliRun size = run("render " + sphere + " -o " + out.string() + ".png --size -5");
  EXPECT_EQ(size.status, 2) << size.err;  // was an internal error, 70, from the PNG encoder
  EXPECT_NE(size.err.find("--size"), std::string::npos) << size.err;
  EXPECT_EQ(run("remesh " + sphere).status, 2);  // -o is required
}

// The output path is checked before the input is read (bunny00 ran 3 s and then said "cannot
// write this format"): here the input does not even exist, and the error is the output's.
TEST(Cli, OutputPathIsCheckedBeforeAnyWork) {
  const auto dir = std::filesystem::temp_directory_path();
  const std::string missing = (dir / "isoquad_cli_no_such_input.off").string();
  const CliRun stl = run("remesh " + missing + " -o " + (dir / "x.stl").string());
  EXPECT_EQ(stl.status, 2);
  EXPECT_NE(stl.err.find("x.stl: cannot write this format"), std::string::npos) << stl.err;
  EXPECT_NE(stl.err.find("[E002]"), std::string::npos) << stl.err;
  const CliRun folder = run("remesh " + missing + " -o /nonexistent_isoquad/x.obj");
  EXPECT_EQ(folder.status, 2);
  EXPECT_NE(folder.err.find("the folder /nonexistent_isoquad does not exist [E001]"),
            std::string::npos)
      << folder.err;
  const CliRun is_dir = run("remesh " + missing + " -o " + dir.string());
  EXPECT_EQ(is_dir.status, 2);
  EXPECT_EQ(is_dir.err.find("no such file"), std::string::npos) << is_dir.err;
  const auto file = write_temp("isoquad_cli_a_file", "not a folder");
  const CliRun report = run("remesh " + missing + " -o " + (dir / "x.obj").string() + " --report " +
                            (file / "report").string());
  EXPECT_EQ(report.status, 2);
  EXPECT_NE(report.err.find(file.string() + " is not a folder [E001]"), std::string::npos)
      << report.err;
  std::filesystem::remove(file);
  const CliRun seg = run("segment " + missing + " -o " + (dir / "x.stl").string());
  EXPECT_NE(seg.err.find("cannot write this format"), std::string::npos) << seg.err;
  const CliRun png = run("render " + missing + " -o /nonexistent_isoquad/x.png");
  EXPECT_NE(png.err.find("does not exist [E001]"), std::string::npos) << png.err;
  const CliRun param = run("param " + missing + " --svg /nonexistent_isoquad/x.svg");
  EXPECT_NE(param.err.find("does not exist [E001]"), std::string::npos) << param.err;
  // The input's own error once the output is fine.
  const CliRun input = run("remesh " + missing + " -o " + (dir / "x.obj").string());
  EXPECT_EQ(input.status, 2);
  EXPECT_NE(input.err.find("no such file"), std::string::npos) << input.err;
}

// With --json, stdout is one JSON document whatever happens. A sphere with a vertex moved onto
// its neighbour (coincident vertices, zero-area triangles) once had a singular system, and
// CHOLMOD printed "CHOLMOD warning: not positive definite" on stdout before the document (then
// E551). The zero-area repair (W116) now collapses the edge first: each is remeshed, valid, with
// the repair in the JSON.
TEST(Cli, RemeshJsonStdoutIsOneDocumentWhateverHappens) {
  const auto in = std::filesystem::temp_directory_path() / "isoquad_cli_coincident.off";
  const auto out = std::filesystem::temp_directory_path() / "isoquad_cli_coincident_quads.obj";
  for (const uint32_t v : {5u, 40u, 100u, 200u, 300u}) {
    isoquad::PolyMesh m = isoquad::test::icosphere(3);
    m.positions[v] = m.positions[m.face(0)[0] == v ? m.face(0)[1] : m.face(0)[0]];
    for (std::size_t f = 0; f < m.num_faces(); ++f)  // a neighbour of v instead, where it has one
      for (std::size_t k = 0; k < 3; ++k)
        if (m.face(f)[k] == v) m.positions[v] = m.positions[m.face(f)[(k + 1) % 3]];
    isoquad::write_mesh(in, m);
    const CliRun r = run("remesh --quads 300 --json " + in.string() + " -o " + out.string());
    EXPECT_EQ(r.out.find("CHOLMOD"), std::string::npos) << v << r.out;
    nlohmann::json doc;
    ASSERT_NO_THROW(doc = nlohmann::json::parse(r.out)) << v << ": " << r.out;
    ASSERT_EQ(r.status, 0) << v << r.err;
    const auto& q = doc["quality"];
    EXPECT_TRUE(q["pure_quad"].get<bool>() && q["edge_manifold"].get<bool>() &&
                q["vertex_manifold"].get<bool>() && q["oriented"].get<bool>())
        << v;
    EXPECT_TRUE(q["same_topology"].get<bool>()) << v;
    EXPECT_EQ(q["scaled_jacobian"]["at_most_0.001"], 0) << v;
    uint32_t repaired = 0;
    for (const auto& w : doc["warnings"])
      if (w["code"] == "W116") repaired += w["count"].get<uint32_t>();
    EXPECT_EQ(repaired, 1u) << v;
    for (const auto& c : doc["components"]) {
      EXPECT_EQ(c.value("four_sided_reason", ""), "") << v;
      EXPECT_EQ(c.value("triangle_split_reason", ""), "") << v;
    }
  }
  std::filesystem::remove(in);
  std::filesystem::remove(out);
}

// The JSON has the process's peak resident memory (getrusage), for bench/peers and batch users:
// any process that read and remeshed a mesh has used more than a megabyte.
TEST(Cli, RemeshJsonHasThePeakMemory) {
  const auto in = std::filesystem::temp_directory_path() / "isoquad_cli_peak.off";
  const auto out = std::filesystem::temp_directory_path() / "isoquad_cli_peak_quads.obj";
  isoquad::write_mesh(in, isoquad::test::icosphere(3));
  const CliRun r = run("remesh -q --quads 300 --json " + in.string() + " -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_TRUE(doc["peak_rss_bytes"].is_number_integer()) << r.out;
  EXPECT_GT(doc["peak_rss_bytes"].get<long long>(), 1LL << 20);
  std::filesystem::remove(in);
  std::filesystem::remove(out);
}

// Every repair preparation makes is said by remesh on stderr (unless -q) and listed in the
// JSON's "warnings" (before, only `info` told them): here a duplicate face and an unused vertex.
TEST(Cli, RemeshSaysEveryRepairOnStderrAndInTheJson) {
  const auto in = std::filesystem::temp_directory_path() / "isoquad_cli_repairs.off";
  const auto out = std::filesystem::temp_directory_path() / "isoquad_cli_repairs_quads.obj";
  isoquad::PolyMesh m = isoquad::test::icosphere(2);
  const auto first = m.face(0);
  m.add_face({first[0], first[1], first[2]});
  m.positions.push_back({5, 5, 5});
  isoquad::write_mesh(in, m);
  const CliRun r = run("remesh --quads 300 --json " + in.string() + " -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("warning: dropped 1 duplicate faces [W106]"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("warning: ignored 1 vertices that no face uses [W108]"), std::string::npos)
      << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  std::set<std::string> codes;
  for (const auto& w : doc["warnings"]) codes.insert(w["code"].get<std::string>());
  EXPECT_EQ(codes, (std::set<std::string>{"W106", "W108"}));
  const CliRun quiet = run("remesh -q --quads 300 " + in.string() + " -o " + out.string());
  ASSERT_EQ(quiet.status, 0) << quiet.err;
  EXPECT_TRUE(quiet.err.empty()) << quiet.err;
  std::filesystem::remove(in);
  std::filesystem::remove(out);
}

// A mistyped subcommand or option is named, with the nearest valid one (CLI11 said "A
// subcommand is required" for `isoquad remsh`), and the status is that of invalid input.
TEST(Cli, UnknownSubcommandAndOptionAreNamedWithASuggestion) {
  const CliRun sub = run("remsh");
  EXPECT_EQ(sub.status, 2);
  EXPECT_NE(sub.err.find("isoquad: error: unknown subcommand 'remsh'; did you mean 'remesh'?"),
            std::string::npos)
      << sub.err;
  const CliRun far = run("frobnicate");
  EXPECT_EQ(far.status, 2);
  EXPECT_NE(far.err.find("unknown subcommand 'frobnicate'\n"), std::string::npos) << far.err;
  const std::string sphere = (isoquad::test::data_dir() / "sphere.off").string();
  const auto out = std::filesystem::temp_directory_path() / "isoquad_cli_typo.obj";
  const CliRun opt = run("remesh " + sphere + " -o " + out.string() + " --quad 5");
  EXPECT_EQ(opt.status, 2);
  EXPECT_NE(opt.err.find("unknown option '--quad' for remesh; did you mean '--quads'?"),
            std::string::npos)
      << opt.err;
  const CliRun negated = run("layout " + sphere + " --no-improve-corner");
  EXPECT_EQ(negated.status, 2);
  EXPECT_NE(negated.err.find("did you mean '--no-improve-corners'?"), std::string::npos)
      << negated.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(Cli, SegmentationModeIsCheckedAndReported) {
  const std::string sphere = (isoquad::test::data_dir() / "sphere.off").string();
  const auto out = std::filesystem::temp_directory_path() / "isoquad_cli_segmentation.obj";
  const CliRun bad = run("remesh " + sphere + " -o " + out.string() + " --segmentation voronoi");
  EXPECT_EQ(bad.status, 2);
  EXPECT_FALSE(std::filesystem::exists(out));
  // The field mode runs; on the sphere its traced patches fall back to VSA, and the JSON says so.
  const CliRun r =
      run("remesh " + sphere + " -o " + out.string() + " --quads 600 --segmentation field --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_EQ(doc["options"]["segmentation"], "field");
  const auto& c = doc["components"][0];
  EXPECT_TRUE(c["layout_source"] == "field" ||
              !c["field"]["fallback_reason"].get<std::string>().empty());
  EXPECT_EQ(c["field"]["singularities"], 8);
  std::filesystem::remove(out);
  const CliRun seg = run("segment " + sphere + " --quads 600 --segmentation field --json");
  ASSERT_EQ(seg.status, 0) << seg.err;
  EXPECT_GT(nlohmann::json::parse(seg.out)[0]["patches"].get<int>(), 1);
}

// Options that only mean something for VSA's patches are refused in field mode, before any
// work, naming the option; layout and param take --segmentation as remesh and segment do.
TEST(Cli, VsaOnlyOptionsAreRefusedInFieldMode) {
  const std::string sphere = (isoquad::test::data_dir() / "sphere.off").string();
  const auto out = std::filesystem::temp_directory_path() / "isoquad_cli_vsa_only.obj";
  for (const std::string option : {"--patches 12", "--corners local", "--no-tip-split",
                                   "--no-patch-rounds", "--no-misfit-split", "--split-patches"}) {
    const CliRun r =
        run("remesh " + sphere + " -o " + out.string() + " --segmentation field " + option);
    EXPECT_EQ(r.status, 2) << option;
    EXPECT_NE(r.err.find(option.substr(0, option.find(' '))), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("only means something with --segmentation vsa"), std::string::npos)
        << r.err;
    EXPECT_FALSE(std::filesystem::exists(out));
  }
  for (const std::string sub : {"segment", "layout", "param"})
    EXPECT_EQ(run(sub + " " + sphere + " --segmentation field --patches 12").status, 2) << sub;
  // The same options are taken in VSA mode.
  const CliRun vsa = run("remesh " + sphere + " -o " + out.string() +
                         " --quads 600 --segmentation vsa --patches 12 -q");
  EXPECT_EQ(vsa.status, 0) << vsa.err;
  std::filesystem::remove(out);
  for (const std::string sub : {"layout", "param"}) {
    const CliRun r = run(sub + " " + sphere + " --quads 600 --segmentation field --json");
    ASSERT_EQ(r.status, 0) << sub << ": " << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)[0]["layout_source"], "field") << sub;
  }
}

TEST(Cli, SegmentWritesPatchesPictureAndSummary) {
  const auto dir = std::filesystem::temp_directory_path();
  const auto ply = dir / "isoquad_cli_patches.ply", png = dir / "isoquad_cli_patches.png";
  const CliRun r = run("segment " + (isoquad::test::data_dir() / "elephant.off").string() +
                       " --patches 12 -o " + ply.string() + " --png " + png.string() + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_EQ(doc.size(), 1u);
  EXPECT_GE(doc[0]["patches"].get<int>(), 12);
  EXPECT_EQ(doc[0]["euler"], -4);  // elephant: genus 3
  EXPECT_EQ(doc[0]["meta_vertices"].get<int>() - doc[0]["meta_edges"].get<int>() +
                doc[0]["meta_faces"].get<int>(),
            -4);
  // The PLY reads back as a closed genus-3 surface; the PNG starts with the PNG signature.
  const CliRun info = run("info --json " + ply.string());
  ASSERT_EQ(info.status, 0) << info.err;
  EXPECT_EQ(nlohmann::json::parse(info.out)["components"][0]["genus"], 3);
  std::ifstream in(png, std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  EXPECT_EQ(std::string(sig + 1, 3), "PNG");
  std::filesystem::remove(ply);
  std::filesystem::remove(png);
  // Asking for an impossible output format fails cleanly, without a file.
  const CliRun bad = run("segment " + (isoquad::test::data_dir() / "sphere.off").string() + " -o " +
                         (dir / "x.stl").string());
  EXPECT_EQ(bad.status, 2);
  EXPECT_FALSE(std::filesystem::exists(dir / "x.stl"));
}

TEST(Cli, LayoutReportsChartsAndLengths) {
  const CliRun r =
      run("layout " + (isoquad::test::data_dir() / "rotor.off").string() + " --quads 800 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_EQ(doc.size(), 1u);
  const auto& j = doc[0];
  int64_t quads = 0;
  for (const auto& c : j["charts"]) {
    EXPECT_GE(c["width"].get<int>(), 1);
    EXPECT_GE(c["height"].get<int>(), 1);
    EXPECT_EQ(c["corner_meta_vertices"].size(), 4u);
    quads += c["width"].get<int64_t>() * c["height"].get<int64_t>();
  }
  EXPECT_EQ(quads, j["quads"].get<int64_t>());
  EXPECT_NEAR(double(quads), 800, 80);
  EXPECT_EQ(j["meta_edges_detail"].size(), j["meta_edges"].get<size_t>());
  // Each chart's sides: opposite sides add up to its width and height, and the side targets are
  // the sums of their meta-edges' targets.
  for (const auto& c : j["charts"]) {
    ASSERT_EQ(c["side_edges"].size(), 4u);
    ASSERT_EQ(c["side_targets"].size(), 4u);
    for (int s = 0; s < 4; ++s) {
      ASSERT_FALSE(c["side_edges"][s].empty());
      int64_t length = 0;
      double target = 0;
      for (const auto& e : c["side_edges"][s]) {
        length += j["meta_edges_detail"][e.get<size_t>()]["length"].get<int64_t>();
        target += j["meta_edges_detail"][e.get<size_t>()]["target"].get<double>();
      }
      EXPECT_EQ(length, c[s % 2 == 0 ? "width" : "height"].get<int64_t>());
      EXPECT_NEAR(target, c["side_targets"][s].get<double>(), 1e-9);
    }
  }
  for (const auto& e : j["meta_edges_detail"]) {
    EXPECT_GE(e["length"].get<int>(), 1);
    EXPECT_GE(e["rotation"].get<int>(), 0);
    EXPECT_LE(e["rotation"].get<int>(), 3);
  }
  // A genus-1 surface has no net singularity: valence-3 and valence-5 vertices balance.
  const auto& v = j["interior_valence"];
  const int v3 = v.contains("3") ? v["3"].get<int>() : 0,
            v5 = v.contains("5") ? v["5"].get<int>() : 0,
            v6 = v.contains("6") ? v["6"].get<int>() : 0;
  EXPECT_EQ(v3, v5 + 2 * v6);
  // A refused option value is invalid input, as everywhere (CLI11 exited 105).
  EXPECT_EQ(
      run("layout " + (isoquad::test::data_dir() / "rotor.off").string() + " --corners sideways")
          .status,
      2);
}

TEST(Cli, RemeshProgressBarOnATerminalAndLinesOtherwise) {
  const std::string sphere = (isoquad::test::data_dir() / "sphere.off").string();
  const auto out = std::filesystem::temp_directory_path() / "isoquad_cli_progress.obj";
  // On a pseudo-terminal: one line redrawn in place, "\r\033[K[###...] 42% map, 0:01 elapsed,
  // about 0:02 left", the stage names as they begin, ending at 100% done and a newline.
  const CliRun tty = isoquad::test::on_terminal(
      {ISOQUAD_CLI_PATH, "remesh", sphere, "-o", out.string(), "--quads", "300", "--json"});
  ASSERT_EQ(tty.status, 0) << tty.err;
  const std::string redraw = "\r\033[K[";
  std::vector<std::string> bars;
  for (std::size_t at = tty.err.find(redraw); at != std::string::npos;) {
    const std::size_t next = tty.err.find('\r', at + 1);
    bars.push_back(tty.err.substr(at + redraw.size(),
                                  next == std::string::npos ? next : next - at - redraw.size()));
    at = next == std::string::npos ? next : tty.err.find(redraw, next);
  }
  ASSERT_GE(bars.size(), 8u) << tty.err;
  for (const char* stage : {"% prepare", "% segment", "% layout", "% map", "% extract", "% repair",
                            "% quality", "100% done"})
    EXPECT_TRUE(
        std::any_of(bars.begin(), bars.end(),
                    [&](const std::string& b) { return b.find(stage) != std::string::npos; }))
        << stage << " in " << tty.err;
  for (const std::string& b : bars) EXPECT_NE(b.find(" elapsed"), std::string::npos) << b;
  EXPECT_TRUE(std::any_of(bars.begin(), bars.end(), [](const std::string& b) {
    return b.find(" left") != std::string::npos;
  })) << tty.err;
  EXPECT_NE(bars.back().find("] 100% done, "), std::string::npos) << bars.back();
  EXPECT_EQ(tty.err.back(), '\n');  // the bar's line ended, and nothing after it
  EXPECT_NE(tty.err.find("\r\033[Kcomponent 0: segment"), std::string::npos) << tty.err;

  // Not a terminal: no redraws, a plain line per stage begun among the lines said.
  const CliRun plain = run("remesh " + sphere + " -o " + out.string() + " --quads 300 --json");
  ASSERT_EQ(plain.status, 0) << plain.err;
  EXPECT_EQ(plain.err.find('\r'), std::string::npos) << plain.err;
  EXPECT_EQ(plain.err.find('\033'), std::string::npos) << plain.err;
  for (const char* line : {"remesh:   0% prepare, 0:0", "% segment, ", "% layout, ", "% map, ",
                           "% extract, ", "% repair, ", "% quality, ", "remesh: 100% done, "})
    EXPECT_NE(plain.err.find(line), std::string::npos) << line << " in " << plain.err;
  EXPECT_NE(plain.err.find("component 0: segment"), std::string::npos) << plain.err;

  // -q: neither.
  const CliRun quiet = run("remesh " + sphere + " -o " + out.string() + " --quads 300 -q");
  ASSERT_EQ(quiet.status, 0) << quiet.err;
  EXPECT_EQ(quiet.err, "");
  const CliRun quiet_tty = isoquad::test::on_terminal(
      {ISOQUAD_CLI_PATH, "remesh", sphere, "-o", out.string(), "--quads", "300", "-q"});
  ASSERT_EQ(quiet_tty.status, 0) << quiet_tty.err;
  EXPECT_EQ(quiet_tty.err, "");
  std::filesystem::remove(out);
}

TEST(Cli, AllowTopologyChangeIsAnOptionEchoedInTheJson) {
  const std::string sphere = (isoquad::test::data_dir() / "sphere.off").string();
  const auto out = std::filesystem::temp_directory_path() / "isoquad_cli_topology.obj";
  EXPECT_NE(run("remesh --help").out.find("--allow-topology-change"), std::string::npos);
  for (const bool allow : {false, true}) {
    const CliRun r = run("remesh " + sphere + " -o " + out.string() + " --quads 300 -q --json" +
                         (allow ? " --allow-topology-change" : ""));
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["options"]["allow_topology_change"], allow);
    EXPECT_EQ(r.out.find("W113"), std::string::npos);
  }
  std::filesystem::remove(out);
}

TEST(Cli, RemeshQualityAndParamOnSampleMeshes) {
  const auto dir = std::filesystem::temp_directory_path();
  const auto out = dir / ("isoquad_cli_quads_" + std::to_string(::getpid()) + ".ply");
  const std::string in = (isoquad::test::data_dir() / "rotor.off").string();
  const CliRun r = run("remesh " + in + " -o " + out.string() + " --quads 800 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("component 0: segment"), std::string::npos) << r.err;  // progress
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["quality"]["pure_quad"].get<bool>());
  EXPECT_TRUE(j["quality"]["same_topology"].get<bool>());
  const CliRun q = run("quality --json " + out.string() + " --reference " + in);
  ASSERT_EQ(q.status, 0) << q.err;
  const auto jq = nlohmann::json::parse(q.out);
  EXPECT_EQ(jq["faces"], j["quads"]);
  EXPECT_EQ(jq["topology"], j["quality"]["topology"]);
  // --worst lists the worst faces, smallest first; the first is the minimum of the report.
  const CliRun w = run("quality --json --worst 5 " + out.string() + " --reference " + in);
  ASSERT_EQ(w.status, 0) << w.err;
  const auto jw = nlohmann::json::parse(w.out)["worst"];
  ASSERT_EQ(jw.size(), 5u);
  EXPECT_DOUBLE_EQ(jw[0]["scaled_jacobian_surface"].get<double>(),
                   jq["scaled_jacobian_surface"]["min"].get<double>());
  for (std::size_t i = 1; i < jw.size(); ++i) {
    EXPECT_LE(jw[i - 1]["scaled_jacobian_surface"].get<double>(),
              jw[i]["scaled_jacobian_surface"].get<double>());
    EXPECT_LT(jw[i]["face"].get<int>(), jq["faces"].get<int>());
  }
  const CliRun plain = run("quality --worst 2 " + out.string() + " --reference " + in);
  EXPECT_NE(plain.out.find("face " + std::to_string(jw[1]["face"].get<int>()) + ":"),
            std::string::npos)
      << plain.out;
  EXPECT_NE(run("quality --worst 2 " + out.string()).status, 0);  // needs --reference
  // The invalid count is labelled as against each quad's own normal; the feature coverage is
  // measured at --feature-angle (no dihedral angle is above 180 degrees).
  EXPECT_NE(plain.out.find("against each quad's own normal"), std::string::npos) << plain.out;
  EXPECT_NE(plain.out.find(fmt::format("{} at most 0.001 (not valid",
                                       jq["scaled_jacobian"]["at_most_0.001"].get<int>())),
            std::string::npos)
      << plain.out;
  EXPECT_GT(jq["feature_coverage"]["length"].get<double>(), 0);
  EXPECT_EQ(jq["feature_coverage"], j["quality"]["feature_coverage"]);
  const CliRun wide =
      run("quality --json --feature-angle 180 " + out.string() + " --reference " + in);
  ASSERT_EQ(wide.status, 0) << wide.err;
  EXPECT_EQ(nlohmann::json::parse(wide.out)["feature_coverage"]["length"].get<double>(), 0.0);
  EXPECT_NE(run("quality --feature-angle 30 " + out.string()).status, 0);  // needs --reference
  std::filesystem::remove(out);
  const auto obj = dir / ("isoquad_cli_param_" + std::to_string(::getpid()) + ".obj");
  const CliRun p = run("param " + in + " --quads 800 -o " + obj.string() + " --json");
  ASSERT_EQ(p.status, 0) << p.err;
  EXPECT_TRUE(nlohmann::json::parse(p.out)[0]["certified"].get<bool>());
  std::ifstream objin(obj);
  std::string line;
  std::size_t vt = 0;
  while (std::getline(objin, line)) vt += line.rfind("vt ", 0) == 0;
  EXPECT_GT(vt, 0u);
  std::filesystem::remove(obj);
}

// The untangling and layout switches: by default folded quads are untangled (and the JSON says
// how many), --no-untangle leaves the map's lattice points (no move), --split-patches makes every
// patch four-sided first and says so among the layout repairs. Without refinement, which would
// cut the folded quads finer and untangle those instead, nor patch rounds, which would remesh
// from other patches where the untangled quads stay far.
TEST(Cli, RemeshUntangleAndSplitSwitches) {
  const auto out = std::filesystem::temp_directory_path() /
                   ("isoquad_cli_switches_" + std::to_string(::getpid()) + ".obj");
  const std::string in = (isoquad::test::data_dir() / "fandisk.off").string();
  const std::string base = "remesh " + in + " -o " + out.string() +
                           " --quads 600 --json --fold-rounds 0 --no-refine --no-patch-rounds";
  const CliRun a = run(base);
  ASSERT_EQ(a.status, 0) << a.err;
  const auto ja = nlohmann::json::parse(a.out);
  const auto& ua = ja["components"][0]["untangle"];
  EXPECT_LE(ua["folded_after"].get<int>(), ua["folded_before"].get<int>());
  EXPECT_EQ(ja["quality"]["scaled_jacobian_surface"]["nonpositive"], ua["nonpositive"]);
  EXPECT_LE(ua["nonpositive"].get<int>(), ua["degenerate"].get<int>());
  EXPECT_EQ(ja["components"][0]["fold_rounds"]["tried"].get<int>(), 0);
  EXPECT_EQ(ja["components"][0]["corners_retried"]["tried"].get<int>(), 0);
  // With rounds of thicker patches (the default), never more folded quads than without.
  const CliRun d = run("remesh " + in + " -o " + out.string() + " --quads 600 --json");
  ASSERT_EQ(d.status, 0) << d.err;
  const auto jd = nlohmann::json::parse(d.out);
  const auto& rd = jd["components"][0]["fold_rounds"];
  EXPECT_LE(rd["kept"].get<int>(), rd["tried"].get<int>());
  EXPECT_LE(rd["tried"].get<int>(), 2);
  if (ua["folded_after"].get<int>() == 0 && ua["collapsed"].get<int>() == 0) {
    EXPECT_EQ(rd["tried"].get<int>(), 0);
  }
  EXPECT_LE(jd["quality"]["scaled_jacobian_surface"]["nonpositive"].get<int>(),
            ua["nonpositive"].get<int>());
  EXPECT_EQ(jd["quality"]["scaled_jacobian_surface"]["nonpositive"],
            jd["components"][0]["untangle"]["nonpositive"]);
  const CliRun b = run(base + " --no-untangle");
  ASSERT_EQ(b.status, 0) << b.err;
  const auto jb = nlohmann::json::parse(b.out);
  EXPECT_EQ(jb["components"][0]["untangle"]["moves"].get<int>(), 0);
  EXPECT_EQ(jb["quality"]["scaled_jacobian_surface"]["nonpositive"], ua["folded_before"]);
  const CliRun c = run(base + " --split-patches");
  ASSERT_EQ(c.status, 0) << c.err;
  const auto jc = nlohmann::json::parse(c.out);
  EXPECT_TRUE(jc["quality"]["pure_quad"].get<bool>());
  EXPECT_TRUE(jc["quality"]["same_topology"].get<bool>());
  EXPECT_TRUE(jc["options"]["split_patches"].get<bool>());
  bool split = false;
  for (const auto& s : jc["components"][0]["layout_repairs"])
    split |= s.get<std::string>().find("four-sided") != std::string::npos;
  EXPECT_TRUE(split) << jc["components"][0]["layout_repairs"].dump();
  std::filesystem::remove(out);
}

// Where diagonal collapses alone remove every fold and leave the quads within 1% of the
// diagonal, they are the repair: no round of thicker patches is tried (each costs a map), and the
// output is the one without rounds, byte for byte. fandisk at 1,200 quads: 15 quads fold after
// the map, and two collapses remove the folds the untangler leaves.
TEST(Cli, CollapsesThatSufficeSkipTheFoldRounds) {
  const auto dir = std::filesystem::temp_directory_path();
  const std::string tag = std::to_string(::getpid());
  const auto with = dir / ("isoquad_cli_rounds_" + tag + ".obj"),
             without = dir / ("isoquad_cli_norounds_" + tag + ".obj");
  const std::string in = (isoquad::test::data_dir() / "fandisk.off").string();
  const CliRun d = run("remesh " + in + " -o " + with.string() + " --quads 1200 --json");
  ASSERT_EQ(d.status, 0) << d.err;
  const auto jd = nlohmann::json::parse(d.out);
  const auto& c = jd["components"][0];
  EXPECT_GT(c["untangle"]["folded_before"].get<int>(), 0);
  EXPECT_GT(c["untangle"]["collapsed"].get<int>(), 0);
  EXPECT_EQ(c["untangle"]["nonpositive"].get<int>(), 0);
  EXPECT_EQ(c["fold_rounds"]["tried"].get<int>(), 0);
  EXPECT_LT(jd["quality"]["hausdorff"].get<double>(), 0.01);
  const CliRun z =
      run("remesh " + in + " -o " + without.string() + " --quads 1200 --fold-rounds 0 --quiet");
  ASSERT_EQ(z.status, 0) << z.err;
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream s(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(s), {});
  };
  EXPECT_EQ(slurp(with), slurp(without));
  std::filesystem::remove(with);
  std::filesystem::remove(without);
}

// A plate whose three triangles on one line no repair can open (flipping their edges only moves
// the zero area): neither the patches nor the triangle split give valid quads, so remesh stops
// with E604 naming the place, and leaves no file; --allow-invalid keeps the quads with W117.
TEST(Cli, RemeshWithNoValidAlternativeIsAnErrorUnlessAllowed) {
  const auto in = write_temp("isoquad_cli_collinear.off",
                             "OFF\n8 8 0\n6 -4 0\n9 0 0\n6 0 0\n3 0 0\n1.5 0 0\n4.5 0 0\n7.5 0 0\n"
                             "4.5 4 0\n3 0 1 2\n3 0 2 3\n3 3 2 4\n3 2 1 6\n3 2 6 4\n3 4 6 5\n"
                             "3 5 6 7\n3 4 5 7\n");
  const auto out = std::filesystem::temp_directory_path() / "isoquad_cli_collinear_quads.obj";
  std::filesystem::remove(out);
  const CliRun r = run("remesh -q " + in.string() + " -o " + out.string());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("[E604]"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("near input face"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--allow-invalid"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  const CliRun kept =
      run("remesh -q --json --allow-invalid " + in.string() + " -o " + out.string());
  ASSERT_EQ(kept.status, 0) << kept.err;
  const auto doc = nlohmann::json::parse(kept.out);
  uint32_t said = 0;
  for (const auto& w : doc["warnings"])
    if (w["code"] == "W117") said += w["count"].get<uint32_t>();
  EXPECT_GT(said, 0u);
  EXPECT_EQ(said, doc["quality"]["scaled_jacobian"]["at_most_0.001"].get<uint32_t>());
  EXPECT_TRUE(doc["options"]["allow_invalid"].get<bool>());
  std::filesystem::remove(in);
  std::filesystem::remove(out);
}

TEST(Cli, RemeshFailureLeavesNoOutput) {
  const auto bad = write_temp("isoquad_cli_bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  const auto out = std::filesystem::temp_directory_path() / "isoquad_cli_never.obj";
  std::filesystem::remove(out);
  const CliRun r = run("remesh " + bad.string() + " -o " + out.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("isoquad: error:"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(out));
  std::filesystem::remove(bad);
}

// `remesh --report`: every file is there and valid, report.json agrees with `isoquad quality` on
// the written mesh, and the page shows every picture in a real browser (headless Chromium).
TEST(Cli, RemeshReportFolderAndPageInChromium) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("isoquad_cli_report_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto out = dir / "quads.obj";
  const std::string in = (isoquad::test::data_dir() / "fandisk.off").string();
  const CliRun r = run("remesh " + in + " -o " + out.string() + " --quads 600 --report " +
                       (dir / "report").string() + " --report-width 480");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json report = isoquad::test::expect_valid_report(dir / "report");
  const CliRun q = run("quality --json " + out.string() + " --reference " + in);
  ASSERT_EQ(q.status, 0) << q.err;
  EXPECT_EQ(nlohmann::json::parse(q.out), report.at("quality"));
  // A fixed view is honoured and recorded.
  const CliRun v = run("remesh " + in + " -o " + out.string() + " --quads 300 --view 0 0 -1 " +
                       "--report " + (dir / "front").string() + " --report-width 300 -q");
  ASSERT_EQ(v.status, 0) << v.err;
  EXPECT_EQ(isoquad::test::expect_valid_report(dir / "front").at("view"),
            nlohmann::json::parse("[0.0, 0.0, -1.0]"));
  // Pictures are deterministic: a second run draws the same bytes.
  const CliRun again = run("remesh " + in + " -o " + out.string() + " --quads 300 --view 0 0 -1 " +
                           "--report " + (dir / "again").string() + " --report-width 300 -q");
  ASSERT_EQ(again.status, 0) << again.err;
  for (const char* f :
       {"input.png", "patches.png", "contours.png", "quads.png", "layout.svg", "weights.png"})
    EXPECT_EQ(isoquad::test::slurp(dir / "front" / f), isoquad::test::slurp(dir / "again" / f))
        << f;

  const char* chromium = "/usr/bin/chromium";
  if (!std::filesystem::exists(chromium)) {
    if (std::getenv("ISOQUAD_REQUIRE_BROWSER")) FAIL() << "chromium is not installed";
    GTEST_SKIP() << "chromium is not installed (scripts/install-deps --tests)";
  }
  // The page marks itself with the number of pictures that loaded once everything has.
  const CliRun page =
      shell(std::string(chromium) +
            " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
            " --disable-background-networking --disable-component-update"
            " --disable-sync --user-data-dir=" +
            (dir / "chromium").string() + " --virtual-time-budget=10000 --dump-dom file://" +
            (dir / "report" / "index.html").string());
  ASSERT_EQ(page.status, 0) << page.err;
  std::size_t images = 0;
  for (const auto& f : report.at("files"))
    images += f.get<std::string>().ends_with(".png") || f.get<std::string>().ends_with(".svg");
  EXPECT_NE(page.out.find("data-images=\"" + std::to_string(images) + "/" + std::to_string(images) +
                          "\""),
            std::string::npos)
      << page.out.substr(0, 400);
  EXPECT_NE(page.out.find("<span id=\"quads\">" + report.at("quads").dump() + "</span>"),
            std::string::npos);
  std::filesystem::remove_all(dir);
}

// `isoquad render`: any mesh, triangles or polygons, to a valid PNG; deterministic; --view
// changes the picture.
TEST(Cli, RenderTrianglesAndQuads) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("isoquad_cli_render_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string tri = (isoquad::test::data_dir() / "fandisk.off").string();
  const auto quads = write_temp("isoquad_cli_render_cube.obj",
                                "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\n"
                                "v 0 1 1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\n"
                                "f 4 1 5 8\n");
  for (const std::string& in : {tri, quads.string()}) {
    SCOPED_TRACE(in);
    const CliRun a =
        run("render " + in + " -o " + (dir / "a.png").string() + " --wireframe --size 240");
    ASSERT_EQ(a.status, 0) << a.err;
    isoquad::test::expect_valid_png(dir / "a.png");
    const CliRun b =
        run("render " + in + " -o " + (dir / "b.png").string() + " --wireframe --size 240");
    ASSERT_EQ(b.status, 0) << b.err;
    EXPECT_EQ(isoquad::test::slurp(dir / "a.png"), isoquad::test::slurp(dir / "b.png"));
    const CliRun c = run("render " + in + " -o " + (dir / "c.png").string() +
                         " --wireframe --size 240 --view 0 -1 0");
    ASSERT_EQ(c.status, 0) << c.err;
    EXPECT_NE(isoquad::test::slurp(dir / "a.png"), isoquad::test::slurp(dir / "c.png"));
  }
  const CliRun bad =
      run("render " + (dir / "missing.off").string() + " -o " + (dir / "x.png").string());
  EXPECT_EQ(bad.status, 2);
  EXPECT_FALSE(std::filesystem::exists(dir / "x.png"));
  std::filesystem::remove_all(dir);
  std::filesystem::remove(quads);
}

// `--patches auto` is the default (the issue's `--patches K|auto`); a K that is neither a
// count nor auto is refused with a message that names the option.
TEST(Cli, PatchesAutoIsTheDefault) {
  const std::string sphere = (isoquad::test::data_dir() / "sphere.off").string();
  const CliRun a = run("segment " + sphere + " --json");
  const CliRun b = run("segment " + sphere + " --patches auto --json");
  ASSERT_EQ(a.status, 0) << a.err;
  ASSERT_EQ(b.status, 0) << b.err;
  EXPECT_GT(a.out.size(), 100u);
  EXPECT_EQ(a.out, b.out);
  const CliRun c = run("segment " + sphere + " --patches 6 --json");
  ASSERT_EQ(c.status, 0) << c.err;
  EXPECT_NE(c.out, a.out);
  const CliRun d = run("segment " + sphere + " --patches many");
  EXPECT_NE(d.status, 0);
  EXPECT_NE(d.err.find("--patches"), std::string::npos) << d.err;
}

TEST(Cli, ThreadCountDoesNotChangeTheOutput) {
  // bunny00 takes every parallel path: the elimination order beside the segmentation, the
  // locked map beside the relaxation, the geodesic lengths, the corner refinement.
  ISOQUAD_CORPUS_MESH(in, "bunny00.off");
  const auto dir = std::filesystem::temp_directory_path();
  const std::string tag = std::to_string(::getpid());
  const auto one = dir / ("isoquad_cli_threads1_" + tag + ".obj");
  const auto two = dir / ("isoquad_cli_threads2_" + tag + ".obj");
  const CliRun a =
      run("remesh " + in.string() + " -o " + one.string() + " --quads 1500 --threads 1");
  ASSERT_EQ(a.status, 0) << a.err;
  const CliRun b =
      run("remesh " + in.string() + " -o " + two.string() + " --quads 1500 --threads 2");
  ASSERT_EQ(b.status, 0) << b.err;
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream s(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(s), {});
  };
  const std::string x = slurp(one), y = slurp(two);
  EXPECT_GT(x.size(), 10000u);
  EXPECT_TRUE(x == y) << "the output differs between 1 and 2 threads";
  std::filesystem::remove(one);
  std::filesystem::remove(two);
}

// --tolerance at the default size: the sphere (0.60% at its default 2,576 quads) asked for
// 0.4% gets one finer run (asked for at least 1.5 times the quads; the layout lands within 10%),
// and the run reported as kept is the output (its distance is the one `quality` measures); that
// is without the local refinement, which reaches 0.4% in the first run (0.388% at 2,746 quads in
// four rounds when this was written). With --quads it is refused: the tolerance chooses the size.
TEST(Cli, ToleranceRemeshesFinerAtTheDefaultSize) {
  const std::string sphere = (isoquad::test::data_dir() / "sphere.off").string();
  const auto out = std::filesystem::temp_directory_path() /
                   ("isoquad_cli_tolerance_" + std::to_string(::getpid()) + ".obj");
  const CliRun a =
      run("remesh " + sphere + " -o " + out.string() +
          " --tolerance 0.004 --tolerance-rounds 1 --no-refine --no-patch-rounds --json");
  ASSERT_EQ(a.status, 0) << a.err;
  const auto j = nlohmann::json::parse(a.out);
  const auto& sizes = j["components"][0]["size_rounds"];
  ASSERT_EQ(sizes["tried"].size(), 2u) << sizes;
  const auto& first = sizes["tried"][0];
  const auto& second = sizes["tried"][1];
  EXPECT_GT(first["hausdorff"].get<double>(), 0.004);
  EXPECT_GE(second["quads"].get<double>(), 1.4 * first["quads"].get<double>());
  const bool finer_kept = second["folded"].get<int>() <= first["folded"].get<int>() &&
                          second["hausdorff"].get<double>() < first["hausdorff"].get<double>();
  EXPECT_EQ(sizes["kept"].get<int>(), finer_kept ? 1 : 0);
  const auto& kept = sizes["tried"][sizes["kept"].get<int>()];
  EXPECT_EQ(j["quads"], kept["quads"]);
  EXPECT_NEAR(j["quality"]["hausdorff"].get<double>(), kept["hausdorff"].get<double>(), 1e-6);
  EXPECT_TRUE(j["quality"]["pure_quad"].get<bool>());
  EXPECT_TRUE(j["quality"]["same_topology"].get<bool>());
  EXPECT_NE(a.err.find("sizes tried for the 0.40% tolerance"), std::string::npos) << a.err;

  // With the refinement: one size; the refined quads are kept within the tolerance, the JSON's
  // `refine` lists the rounds (the first is the unrefined run) and stderr says so.
  const CliRun d = run("remesh " + sphere + " -o " + out.string() +
                       " --tolerance 0.004 --tolerance-rounds 1 --json");
  ASSERT_EQ(d.status, 0) << d.err;
  const auto k = nlohmann::json::parse(d.out);
  const auto& c0 = k["components"][0];
  EXPECT_EQ(c0["size_rounds"]["tried"].size(), 1u) << c0["size_rounds"];
  const auto& refine = c0["refine"];
  ASSERT_GE(refine["tried"].size(), 2u) << refine;
  EXPECT_EQ(refine["kept"].get<std::size_t>() + 1, refine["tried"].size());
  EXPECT_EQ(refine["tried"][0]["quads"], first["quads"]);
  EXPECT_EQ(refine["tried"][0]["marked"], 0);
  EXPECT_GT(refine["tried"][0]["hausdorff"].get<double>(), 0.004);
  const auto& last = refine["tried"][refine["kept"].get<std::size_t>()];
  EXPECT_LE(last["hausdorff"].get<double>(), 0.004);
  EXPECT_EQ(k["quads"], last["quads"]);
  EXPECT_GT(k["quads"].get<double>(), first["quads"].get<double>());
  EXPECT_LT(k["quads"].get<double>(), 2 * first["quads"].get<double>());
  EXPECT_LT(k["quality"]["hausdorff"].get<double>(), 0.004);
  EXPECT_TRUE(k["quality"]["pure_quad"].get<bool>());
  EXPECT_TRUE(k["quality"]["same_topology"].get<bool>());
  EXPECT_NE(d.err.find("refined where far"), std::string::npos) << d.err;

  const CliRun b =
      run("remesh " + sphere + " -o " + out.string() + " --quads 500 --tolerance 0.004 --json");
  EXPECT_NE(b.status, 0);
  EXPECT_NE(b.err.find("tolerance"), std::string::npos) << b.err;
  const CliRun c = run("remesh " + sphere + " -o " + out.string() + " --quads 500 --json");
  ASSERT_EQ(c.status, 0) << c.err;
  EXPECT_TRUE(nlohmann::json::parse(c.out)["components"][0]["size_rounds"]["tried"].empty());
  EXPECT_NE(run("remesh " + sphere + " -o " + out.string() + " --tolerance 2").status, 0);
  std::filesystem::remove(out);
}

TEST(Cli, TipSplitIsReportedAndCanBeTurnedOff) {
  // The bumpy sphere of the extraction tests (every 97th vertex raised by 12%): at 300 quads
  // the first run cuts bumps off, the run with them split is kept, and the progress and the JSON
  // say so; --no-tip-split runs once.
  isoquad::PolyMesh bumpy = isoquad::test::icosphere(4);
  for (std::size_t v = 0; v < bumpy.positions.size(); v += 97)
    bumpy.positions[v] = 1.12 * bumpy.positions[v];
  const auto dir =
      std::filesystem::temp_directory_path() / ("isoquad_cli_tips_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string in = (dir / "bumpy.off").string(), out = (dir / "quads.obj").string();
  isoquad::write_mesh(in, bumpy);
  for (const bool split : {true, false}) {
    const CliRun a = run("remesh " + in + " -o " + out + " --quads 300 --json" +
                         (split ? "" : " --no-tip-split"));
    ASSERT_EQ(a.status, 0) << a.err;
    const auto j = nlohmann::json::parse(a.out);
    EXPECT_EQ(j["options"]["tip_split"].get<bool>(), split);
    const auto& tips = j["components"][0]["tip_split"];
    const auto& tried = tips["tried"];
    if (split) {
      // The run without tips, then at least one with tips; the kept one is the output.
      ASSERT_GE(tried.size(), 2u) << tips;
      EXPECT_EQ(tried[0]["tips"].get<int>(), 0) << tips;
      EXPECT_GT(tried[1]["tips"].get<int>(), 0) << tips;
      const std::size_t kept = tips["kept"].get<std::size_t>();
      ASSERT_GE(kept, 1u) << tips;
      ASSERT_LT(kept, tried.size()) << tips;
      const double distance = tried[kept]["hausdorff"].get<double>();
      EXPECT_LT(distance, tried[0]["hausdorff"].get<double>());
      EXPECT_NEAR(j["quality"]["hausdorff"].get<double>(), distance, 0.1 * distance);
      EXPECT_NE(a.err.find("tips split:"), std::string::npos) << a.err;
      EXPECT_NE(a.err.find("(kept)"), std::string::npos) << a.err;
    } else {
      EXPECT_TRUE(tried.empty()) << tips;
      EXPECT_EQ(a.err.find("split:"), std::string::npos) << a.err;
    }
    EXPECT_TRUE(j["quality"]["pure_quad"].get<bool>());
  }
  std::filesystem::remove_all(dir);
}
