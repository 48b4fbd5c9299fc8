// Input options shared by every subcommand that reads a mesh.
#pragma once

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <limits>
#include <string>
#include <vector>

#include "io/read_mesh.hpp"
#include "isoquad/remesh.hpp"
#include "pipeline/remesh.hpp"
#include "pipeline/sizing.hpp"
#include "prep/prepare.hpp"
#include "seg/segment.hpp"

namespace isoquad::cli {

// A number within [lo, hi], refused with `what` it should be. CLI11's own numeric validators
// print their bounds with %f ("0 not in range 0.000000 to 1797693134862315...").
inline CLI::Validator number_in(double lo, double hi, const std::string& what) {
  return CLI::Validator(
      [=](const std::string& text) {
        double x = 0;
        if (!CLI::detail::lexical_cast(text, x)) return fmt::format("{} is not a number", text);
        if (!(x >= lo && x <= hi)) return fmt::format("{} is not {}", text, what);
        return std::string();
      },
      "NUMBER");
}

struct PrepArgs {
  bool repair = false;
  double weld_eps = 0.0;
  double feature_angle = 60.0;

  ReadOptions read_options() const { return {.drop_degenerate_faces = repair}; }
  // The remesh options these set; every subcommand prepares the input as remesh does with them.
  RemeshOptions remesh_options() const {
    RemeshOptions o;
    o.repair = repair;
    o.weld_epsilon = weld_eps;
    o.feature_angle_deg = feature_angle;
    return o;
  }
  PrepOptions prep_options(const ReadResult& read) const {
    return isoquad::prep_options(remesh_options(), read.unshared_vertices);
  }
};

inline void add_prep_options(CLI::App& sub, PrepArgs& a) {
  sub.add_flag("--repair", a.repair,
               "Detach non-manifold edges and drop faces with fewer than 3 distinct vertices "
               "instead of rejecting the input");
  sub.add_option("--weld-eps", a.weld_eps,
                 "Weld boundary vertices closer than this fraction of the bounding-box diagonal")
      ->capture_default_str()
      ->check(number_in(0, 0.1, "a fraction in [0, 0.1]"));
  sub.add_option("--feature-angle", a.feature_angle,
                 "Dihedral angle in degrees above which an edge is a feature (0: none)")
      ->capture_default_str()
      ->check(number_in(0, 180, "an angle in [0, 180] degrees"));
}

// Patch count, size and seed: shared by the subcommands that segment.
struct PatchArgs {
  uint32_t patches = 0;
  double edge_length = 0, quads = 0;
  uint64_t seed = 1;
};

inline void add_patch_options(CLI::App& sub, PatchArgs& a) {
  sub.add_option("--patches", a.patches,
                 "Number of patches K, or auto (the default): K from the VSA error drop, "
                 "bounded by the target size")
      ->transform(CLI::Validator(
          [](std::string& k) {
            if (k == "auto")
              k = "0";  // 0 is how the options say automatic
            else if (k.find_first_not_of("0") == std::string::npos)
              return std::string("a patch count must be positive (or auto)");
            return std::string();
          },
          "K|auto"));
  auto* el = sub.add_option("--edge-length", a.edge_length, "Target quad edge length (input units)")
                 ->check(number_in(std::numeric_limits<double>::min(),
                                   std::numeric_limits<double>::max(), "a positive length"));
  sub.add_option("--quads", a.quads, "Target number of quads (the size is tuned to land near it)")
      ->check(number_in(1, 1e9, "a quad count in [1, 1e9]"))
      ->excludes(el);
  sub.add_option("--seed", a.seed, "Random seed")->capture_default_str();
}

// Options that only mean something for VSA's patches (their count, the corner choice, their
// repairs) are refused with --segmentation field, before any file is read: the field layout's
// patches and corners come from its traces (a component that falls back to VSA takes VSA's
// defaults).
inline void refuse_vsa_only_with_field(CLI::App& sub, const std::string& segmentation,
                                       std::vector<std::string> vsa_only) {
  sub.parse_complete_callback([&sub, &segmentation, vsa_only = std::move(vsa_only)] {
    if (segmentation != "field") return;
    for (const std::string& name : vsa_only)
      if (sub.count(name) > 0)
        throw CLI::ValidationError(
            name,
            "only means something with --segmentation vsa: the field layout's patches and "
            "corners come from its traces");
  });
}

// Segmentation options for component `c`: its part of the requested size (one budget for the
// whole mesh, shared out by area).
inline SegmentOptions segment_options(const PatchArgs& a, const PreparedMesh& prep, uint32_t c) {
  return SegmentOptions::sized(component_size(prep, c, {a.edge_length, a.quads}).edge_length,
                               a.patches, a.seed);
}

}  // namespace isoquad::cli
