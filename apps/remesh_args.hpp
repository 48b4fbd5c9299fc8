// The options of `isoquad remesh`, shared with `isoquad batch`, which takes every one of them
// and remeshes each file as remesh does.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

#include "isoquad/remesh.hpp"
#include "prep_options.hpp"

namespace isoquad::cli {

struct RemeshArgs {
  std::string input, output, report_dir, weights = "smvc", relax = "adaptive", corners = "global",
                                         segmentation = "vsa";
  PatchArgs patch;
  bool json = false, quiet = false, improve_corners = true, no_untangle = false, no_snap = false,
       split_patches = false, no_tip_split = false, no_refine = false, no_patch_rounds = false,
       no_misfit_split = false, allow_topology_change = false, allow_invalid = false;
  uint32_t smooth = RemeshOptions{}.smooth, fold_rounds = RemeshOptions{}.fold_rounds, threads = 0;
  double tolerance = RemeshOptions{}.tolerance;
  uint32_t tolerance_rounds = RemeshOptions{}.tolerance_rounds;
  std::vector<double> view;
  int report_width = 1200;
  PrepArgs prep;
};

using Say = std::function<void(const std::string&)>;

// Everything but the input, the output, --report, --json and -q.
void add_remesh_options(CLI::App& sub, RemeshArgs& args);
RemeshOptions remesh_options(const RemeshArgs& args);

// Remeshes `input` into `output` (and writes the report folder, when not empty) as
// `isoquad remesh` does, saying its progress (and with `advance`, how far it is); returns the
// run's JSON report, with the quality measurements when `quality` (or a report folder) is asked
// for.
// \throw Error as remesh and the readers and writers do.
std::string remesh_file(const RemeshArgs& args, const std::string& input, const std::string& output,
                        const std::string& report_dir, bool quality, const Say& say,
                        const ProgressCallback& advance = {});

}  // namespace isoquad::cli
