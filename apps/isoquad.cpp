// isoquad: the command line, a thin shell over the library. Only this layer prints and exits.
#include <fmt/format.h>
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "isoquad/error.hpp"
#include "isoquad/remesh.hpp"
#include "isoquad/version.hpp"

namespace {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// "; did you mean 'X'?" for the nearest of `names`, when it is near enough to be a typo.
std::string nearest(const std::string& word, const std::vector<std::string>& names) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const std::string& n : names)
    if (const std::size_t d = edit_distance(word, n); d < best_distance)
      best = n, best_distance = d;
  return best.empty() ? "" : fmt::format("; did you mean '{}'?", best);
}

// CLI11 says "A subcommand is required" for `isoquad remsh` and "The following arguments were
// not expected: 5 --quad" for `--quad 5`: the word at fault, named, with the nearest valid one.
std::string unknown_word(const CLI::App& app, int argc, char** argv) {
  std::vector<std::string> subcommands;
  const CLI::App* sub = nullptr;
  for (const CLI::App* s : app.get_subcommands({})) {
    subcommands.push_back(s->get_name());
    if (argc > 1 && s->get_name() == argv[1]) sub = s;
  }
  if (argc < 2) return "";
  const std::string first = argv[1];
  if (!sub)
    return first.starts_with("-")
               ? ""
               : fmt::format("unknown subcommand '{}'{}", first, nearest(first, subcommands));
  std::vector<std::string> options;
  for (const CLI::Option* o : sub->get_options()) {
    for (const std::string& n : o->get_lnames()) options.push_back("--" + n);
    for (const std::string& n : o->get_fnames())
      if (n.starts_with("no-")) options.push_back("--" + n);
  }
  for (int i = 2; i < argc; ++i) {
    const std::string word = std::string(argv[i]).substr(0, std::string(argv[i]).find('='));
    if (!word.starts_with("--") || word == "--") continue;
    if (std::find(options.begin(), options.end(), word) == options.end())
      return fmt::format("unknown option '{}' for {}{}", word, sub->get_name(),
                         nearest(word, options));
  }
  return "";
}

std::vector<std::string> given_command_line;

}  // namespace

const std::vector<std::string>& isoquad::cli::command_line() { return given_command_line; }

int main(int argc, char** argv) {
  given_command_line.assign(argv, argv + argc);
  isoquad::tune_allocator();
  CLI::App app{"isoquad: triangle mesh to pure quad mesh by temperature contours"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("isoquad ") + isoquad::version());
  std::vector<std::pair<CLI::App*, isoquad::cli::Runner>> commands;
  auto add = [&](auto adder) {
    const std::size_t before = app.get_subcommands({}).size();
    isoquad::cli::Runner run = adder(app);
    commands.push_back({app.get_subcommands({}).at(before), std::move(run)});
  };
  add(isoquad::cli::add_info);
  add(isoquad::cli::add_field);
  add(isoquad::cli::add_segment);
  add(isoquad::cli::add_layout);
  add(isoquad::cli::add_param);
  add(isoquad::cli::add_remesh);
  add(isoquad::cli::add_quality);
  add(isoquad::cli::add_render);
  add(isoquad::cli::add_batch);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version end here too, with status 0. Every refused command line is invalid
    // input, as a refused mesh is (CLI11's own statuses were 104 to 109).
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    const std::string word = unknown_word(app, argc, argv);
    std::fprintf(stderr, "isoquad: error: %s\nRun with --help for more information.\n",
                 word.empty() ? e.what() : word.c_str());
    return static_cast<int>(isoquad::ErrorKind::invalid_input);
  }
  CLI::App* parsed = nullptr;
  for (auto& [sub, run] : commands)
    if (sub->parsed()) parsed = sub;
  // With --json, stdout is one JSON document whatever happens: on failure, the error.
  const CLI::Option* json = parsed ? parsed->get_option_no_throw("--json") : nullptr;
  const auto fail = [&](int status, const std::string& code, const char* what) {
    if (json && json->count() > 0)
      std::cout << nlohmann::json{{"error",
                                   {{"code", code}, {"message", what}, {"exit_status", status}}}}
                       .dump(2)
                << '\n';
    return status;
  };
  try {
    for (auto& [sub, run] : commands)
      if (sub == parsed) return run();
  } catch (const isoquad::Error& e) {
    std::fprintf(stderr, "isoquad: error: %s\n", e.what());
    return fail(e.exit_status(), e.code(), e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "isoquad: internal error: %s\n", e.what());
    return fail(static_cast<int>(isoquad::ErrorKind::internal), "E700", e.what());
  }
  return 0;
}
