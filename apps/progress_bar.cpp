#include "progress_bar.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace isoquad::cli {

std::string clock_time(double seconds) {
  const auto s = static_cast<long>(seconds + 0.5);
  return s >= 3600 ? fmt::format("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
                   : fmt::format("{}:{:02}", s / 60, s % 60);
}

std::string bar_cells(double fraction, int width) {
  const int filled = int(width * std::clamp(fraction, 0.0, 1.0));
  return "[" + std::string(std::size_t(filled), '#') +
         std::string(std::size_t(width - filled), '.') + "]";
}

bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) == 1; }

RemeshProgress::RemeshProgress(bool terminal)
    : terminal_(terminal), t0_(Clock::now()), last_line_(t0_), ticker_([this] { tick(); }) {}

RemeshProgress::~RemeshProgress() { finish(); }

std::string RemeshProgress::status() const {
  const double elapsed = std::chrono::duration<double>(Clock::now() - t0_).count();
  const double f = std::clamp(at_.fraction, 0.0, 1.0);
  // The fraction follows rough stage weights: an estimate only once a twentieth is done.
  const std::string left =
      f >= 0.05 && f < 1 ? fmt::format(", about {} left", clock_time(elapsed * (1 - f) / f)) : "";
  // Rounded down, and 100% only at the end: the last component's lines are said at its end.
  const int percent = at_.stage == "done" ? 100 : std::min(99, int(std::floor(100 * f)));
  return fmt::format("{:3}% {}, {} elapsed{}", percent, at_.stage, clock_time(elapsed), left);
}

void RemeshProgress::draw() {
  fmt::print(stderr, "\r\033[K{} {}", bar_cells(at_.fraction), status());
  std::fflush(stderr);
}

void RemeshProgress::advance(const Progress& p) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (stopped_) return;
  at_ = p;
  started_ = true;
  if (terminal_) {
    draw();
  } else if (p.message.empty() && p.stage != last_stage_) {
    // A stage begun (a line said arrives through say() too).
    fmt::print(stderr, "remesh: {}\n", status());
    last_line_ = Clock::now();
  }
  if (p.message.empty()) last_stage_ = p.stage;
}

void RemeshProgress::say(const std::string& line) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (stopped_) return;
  if (terminal_ && started_) {
    fmt::print(stderr, "\r\033[K{}\n", line);
    draw();
  } else {
    fmt::print(stderr, "{}\n", line);
    last_line_ = Clock::now();
  }
}

void RemeshProgress::tick() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!wake_.wait_for(lock, kRedraw, [this] { return stopped_; })) {
    if (!started_) continue;
    if (terminal_) {
      draw();
    } else if (Clock::now() - last_line_ >= kQuietLine) {
      const double elapsed = std::chrono::duration<double>(Clock::now() - t0_).count();
      fmt::print(stderr, "remesh: still in {}, {} elapsed\n", at_.stage, clock_time(elapsed));
      last_line_ = Clock::now();
    }
  }
}

void RemeshProgress::finish() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (stopped_) return;
    stopped_ = true;
  }
  wake_.notify_all();
  ticker_.join();
  if (terminal_ && started_) fmt::print(stderr, "\n");
}

}  // namespace isoquad::cli
