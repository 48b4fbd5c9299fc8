// The subcommands of the isoquad command line. Each registers its options on the CLI11 app and
// returns the function that runs it (returning the exit status).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace isoquad::cli {

using Runner = std::function<int()>;

Runner add_info(CLI::App& app);
Runner add_segment(CLI::App& app);
Runner add_layout(CLI::App& app);
Runner add_param(CLI::App& app);
Runner add_remesh(CLI::App& app);
Runner add_quality(CLI::App& app);
Runner add_render(CLI::App& app);
Runner add_field(CLI::App& app);
Runner add_batch(CLI::App& app);

// The command line as given (argv[0] first): batch starts a process of its own per file with it.
const std::vector<std::string>& command_line();

}  // namespace isoquad::cli
