// isoquad: the command line, a thin shell over the library. Only this layer prints and exits.
#include <fmt/format.h>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "isoquad/error.hpp"
#include "isoquad/remesh.hpp"
#include "isoquad/version.hpp"

int main(int argc, char** argv) {
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
  add(isoquad::cli::add_segment);
  add(isoquad::cli::add_layout);
  add(isoquad::cli::add_param);
  add(isoquad::cli::add_remesh);
  add(isoquad::cli::add_quality);
  add(isoquad::cli::add_render);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version end here too, with status 0. Every refused command line is invalid
    // input, as a refused mesh is (CLI11's own statuses were 104 to 109).
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    std::fprintf(stderr, "isoquad: error: %s\nRun with --help for more information.\n", e.what());
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
