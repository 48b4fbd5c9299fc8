#include "pipeline/progress.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <iterator>

#include "isoquad/error.hpp"

namespace isoquad {

namespace {

// Where each stage of kComponentStages begins in its component's span on the first pass: rough
// shares of the time (the map, factorized and certified, is the longest); the repairs get the
// rest, 40%, as they often take longer than the first pass.
constexpr double kFirstPassBegins[] = {0, 0.15, 0.25, 0.45, 0.6};
static_assert(std::size(kFirstPassBegins) == std::size(kComponentStages));
// After the first pass, each stage begun takes this share of what is left of the span: small,
// since a repair may run the stages many times (the elephant at 20,000 quads began 50 stages
// after its first pass, its tip rounds whole runs: at 0.2 a share the bar stood at 99% for the
// last 40 of its 57 s; at 0.06 it reaches 98%).
constexpr double kRoundShare = 0.06;

int stage_index(const char* name) {
  for (std::size_t k = 0; k < std::size(kComponentStages); ++k)
    if (std::strcmp(kComponentStages[k], name) == 0) return int(k);
  throw Error(ErrorKind::internal, "E700", fmt::format("unknown progress stage '{}'", name));
}

}  // namespace

ProgressMeter::ProgressMeter(ProgressCallback callback)
    : callback_(std::move(callback)), owner_(std::this_thread::get_id()) {}

void ProgressMeter::send(const std::string& message) {
  if (!callback_) return;
  if (std::this_thread::get_id() != owner_)
    throw Error(ErrorKind::internal, "E700",
                "progress reported from a worker thread (the callback runs on the caller's)");
  callback_({at_.fraction, at_.stage, message});
}

void ProgressMeter::reach(double fraction, const char* stage) {
  at_.fraction = std::max(at_.fraction, fraction);
  at_.stage = stage;
  send("");
}

void ProgressMeter::set_fraction(double fraction) {
  at_.fraction = std::max(at_.fraction, fraction);
}

void ProgressMeter::enter_span(double begin, double end) {
  begin_ = std::max(begin, at_.fraction);
  end_ = std::max(end, begin_);
  within_ = 0;
  last_ = -1;
  rounds_ = false;
}

void ProgressMeter::stage(const char* name) {
  const int k = stage_index(name);
  if (rounds_ || k <= last_) {
    rounds_ = true;
    within_ += (1 - within_) * kRoundShare;
  } else {
    within_ = std::max(within_, kFirstPassBegins[k]);
  }
  last_ = k;
  rounds_ = rounds_ || k + 1 == int(std::size(kComponentStages));  // after "repair", rounds
  at_.fraction = std::max(at_.fraction, begin_ + (end_ - begin_) * within_);
  at_.stage = name;
  send("");
}

void ProgressMeter::say(const std::string& message) { send(message); }

}  // namespace isoquad
