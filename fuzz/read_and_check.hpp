// The body of every reader's fuzz target: the bytes as a file of one format, read and then
// checked as `isoquad info` and `remesh` check it (pipeline/remesh.cpp check_input, whose
// PrepOptions these mirror without linking the pipeline). An isoquad::Error is the expected
// answer to a malformed file; anything else escaping (another exception, an internal Error, a
// sanitizer report, a timeout, an allocation past -malloc_limit_mb) is a bug libFuzzer reports.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <string_view>

#include "io/read_mesh.hpp"
#include "isoquad/error.hpp"
#include "prep/prepare.hpp"

namespace isoquad::fuzz {

// An internal error is an invariant of ours that failed: a bug, not a rejected file.
inline void expect_input_error(const Error& e) {
  if (e.kind() != ErrorKind::internal) return;
  std::fprintf(stderr, "internal error %s: %s\n", e.code().c_str(), e.what());
  std::abort();
}

// --weld-eps values inside its range [0, 0.1] and at the tiny end; each input gets one, picked
// by its size, so that a run stays reproducible. (At 0.1 an STL soup's every vertex is within
// reach of a tenth of the others: the runs went to welding those pairs, at 25 inputs a second.)
inline constexpr double kWeldFractions[] = {1e-3, 1e-2, 1e-300};

// The command line's default (info: diagnosing) and the same with a --weld-eps; then, for what
// only --repair reaches, the reader dropping degenerate faces and preparation detaching
// non-manifold edges (remesh: throwing).
inline void read_and_check(const uint8_t* data, std::size_t size, MeshFormat format) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  for (const bool repair : {false, true}) {
    try {
      const ReadResult read = read_mesh_from_memory(bytes, format, "fuzz", {repair});
      PrepOptions options;
      options.repair = repair;
      options.weld_all = read.unshared_vertices;
      options.diagnose = !repair;
      const bool accepted = !prepare(read.mesh, options).report.has_errors();
      options.weld_epsilon = kWeldFractions[size % std::size(kWeldFractions)];
      prepare(read.mesh, options);
      if (accepted) return;  // --repair would change nothing
    } catch (const Error& e) {
      expect_input_error(e);
      if (e.code() != "E014" && e.code() != "E101") return;
    }
  }
}

}  // namespace isoquad::fuzz
