// ProgressBar: the progress of a long CLI job (DEM import, TIN build, point import, polygon load)
// as one line on stderr: a label, a bar, the percent done and the elapsed time, redrawn in place
// at most kRedrawsPerSecond times a second. It draws only when stderr is a terminal and the
// global --quiet flag was not given (OnStderr), so pipes, logs and tests see nothing of it.
//
// Library calls take the bar as a std::function<void(double fraction)> (Callback()): they know
// how far they are, the CLI decides whether and how to show it. Update() may be called from any
// thread (a streaming import reports from its triangulating task); calls are serialised.
#pragma once

#include <chrono>
#include <functional>
#include <iosfwd>
#include <mutex>
#include <string>

namespace tinbase::cli {

// Set once by main() from the global --quiet flag, before any command runs.
void SetQuiet(bool quiet);
// Whether a bar on stderr is drawn: stderr is a terminal and --quiet was not given.
bool ProgressOnStderr();

class ProgressBar {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr int kRedrawsPerSecond = 5;
  static constexpr int kBarWidth = 30;

  // Draws on `out` when `active`; an inactive bar writes nothing at all.
  ProgressBar(std::string label, bool active, std::ostream& out);
  // A bar on stderr, active when ProgressOnStderr().
  explicit ProgressBar(std::string label);
  // Ends a drawn line that Finish() did not (a failed job), so the error starts a line of its own.
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  bool active() const { return active_; }

  // Records `fraction` of the job done (clamped to [0, 1]; a smaller value than the last shown
  // is ignored, so stages reporting out of order never move the bar back). Draws on the first
  // call and then when 1 / kRedrawsPerSecond has passed since the last drawing.
  void Update(double fraction);
  // As Update, at `now` (tests pass their own clock).
  void Update(double fraction, Clock::time_point now);
  // Draws 100 % and ends the line. Later calls do nothing.
  void Finish();
  // Update as a callback for library calls. REQUIRES: the bar outlives the callback's uses.
  std::function<void(double)> Callback();

 private:
  void Draw(double fraction, Clock::time_point now);

  std::string label_;
  bool active_;
  std::ostream& out_;
  std::mutex mutex_;
  Clock::time_point start_;
  bool drawn_ = false;
  bool finished_ = false;
  double shown_ = 0;
  Clock::time_point last_draw_;
};

// Runs `job(callback)` (a library call given the bar's Callback()) under a bar on stderr labelled
// `label`, and returns its result: the bar is finished when the result is ok, and its line ended
// when not, before the caller prints anything.
template <typename Job>
auto WithProgress(const std::string& label, Job&& job) {
  ProgressBar bar(label);
  auto result = job(bar.Callback());
  if (result.ok()) bar.Finish();
  return result;
}

// "label [#######-----------------------]  23 %  0:04": the line Update draws (after a "\r").
std::string ProgressLine(const std::string& label, double fraction, double seconds);

}  // namespace tinbase::cli
