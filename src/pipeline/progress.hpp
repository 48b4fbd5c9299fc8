// How far a remesh is (isoquad::Progress), from the stages as they begin. The run is shared out
// by remesh_run (preparation, the components by their faces, the quality measurements); each
// component's span by rough stage weights for its first pass through the stages, the rest of it
// to the repairs. A repair runs stages again (fold rounds, corner tries, tips, refinement, more
// patches, finer sizes): each stage begun after the first pass takes a share of what is left of
// the span, so the fraction keeps moving and never goes down, however many rounds run.
#pragma once

#include <string>
#include <thread>

#include "isoquad/remesh.hpp"

namespace isoquad {

// The stages inside a component, in the order of their first pass (isoquad/remesh.hpp documents
// them for callers).
inline constexpr const char* kComponentStages[] = {"segment", "layout", "map", "extract", "repair"};

// Not thread-safe, and need not be: the pipeline begins its stages on the thread that called
// remesh (TBB works inside a stage), and there the callback is called. A report from another
// thread is a bug, refused with Error(internal, E700) where there is a callback.
class ProgressMeter {
 public:
  explicit ProgressMeter(ProgressCallback callback);

  // A stage of the run itself ("prepare", "quality", "done") begins at `fraction`.
  void reach(double fraction, const char* stage);
  // The fraction for the next line said, without a call (a component ended).
  void set_fraction(double fraction);
  // The next component's stages share [begin, end] of the run.
  void enter_span(double begin, double end);
  // A stage of kComponentStages begins in the current span.
  void stage(const char* name);
  // A line said, with how far the run is.
  void say(const std::string& message);

 private:
  void send(const std::string& message);

  ProgressCallback callback_;
  std::thread::id owner_;
  Progress at_;
  double begin_ = 0, end_ = 0;
  double within_ = 0;  // how far the current component is, in [0, 1)
  int last_ = -1;      // the index in kComponentStages of the last stage begun
  bool rounds_ = false;
};

}  // namespace isoquad
