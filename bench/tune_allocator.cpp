// Linked into every benchmark: the allocator set up as the command line sets it
// (isoquad::tune_allocator), before the benchmarks run, so that they time what a user runs.
#include "isoquad/remesh.hpp"

namespace {
const bool tuned = (isoquad::tune_allocator(), true);
}  // namespace
