// Progress on stderr for the commands that run long (remesh, batch): a bar redrawn in place on a
// terminal, plain lines otherwise (a log, a pipe).
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include "isoquad/remesh.hpp"

namespace isoquad::cli {

// m:ss, or h:mm:ss from an hour on.
std::string clock_time(double seconds);

// "[##########..............]": `fraction` (clamped to [0, 1]) of `width` cells filled.
std::string bar_cells(double fraction, int width = 24);

bool stderr_is_terminal();

// One remesh's progress (isoquad::Progress) on stderr.
// On a terminal, one line redrawn in place with \r:
//   [##########..............]  42% map, 0:12 elapsed, about 0:17 left
// with the lines said printed above it; a ticker thread redraws it every second, so that the
// clock moves while a long stage is silent; it ends with a newline.
// Otherwise, a line per stage begun ("remesh:  42% map, 0:12 elapsed, about 0:17 left") among
// the lines said, and "remesh: still in map, ..." when nothing was printed for kQuietLine.
// The library's callback (the caller's thread) and the ticker share it under a lock.
class RemeshProgress {
 public:
  static constexpr std::chrono::seconds kRedraw{1}, kQuietLine{10};

  explicit RemeshProgress(bool terminal);
  ~RemeshProgress();  // finish()
  RemeshProgress(const RemeshProgress&) = delete;
  RemeshProgress& operator=(const RemeshProgress&) = delete;

  void advance(const Progress& p);
  void say(const std::string& line);
  // Stops and joins the ticker (nothing is printed after this returns) and ends the bar's line.
  // Idempotent; also run by the destructor, so that an error's message starts on a line of its
  // own.
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  std::string status() const;  // "42% map, 0:12 elapsed, about 0:17 left"
  void draw();                 // the bar, in place (terminal)
  void tick();

  const bool terminal_;
  const Clock::time_point t0_;
  std::mutex mutex_;
  std::condition_variable wake_;
  Progress at_;
  bool started_ = false, stopped_ = false;
  std::string last_stage_;
  Clock::time_point last_line_;
  std::thread ticker_;
};

}  // namespace isoquad::cli
