#include "apps/tinbase/progress.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <iostream>

namespace tinbase::cli {

namespace {

std::atomic<bool> quiet{false};

}  // namespace

void SetQuiet(bool value) { quiet = value; }

bool ProgressOnStderr() { return !quiet && isatty(STDERR_FILENO) == 1; }

std::string ProgressLine(const std::string& label, double fraction, double seconds) {
  const int filled =
      std::clamp(static_cast<int>(fraction * ProgressBar::kBarWidth), 0, ProgressBar::kBarWidth);
  const auto whole = static_cast<long>(seconds);
  char tail[48];
  std::snprintf(tail, sizeof tail, "] %3d %%  %ld:%02ld", static_cast<int>(fraction * 100),
                whole / 60, whole % 60);
  return label + " [" + std::string(static_cast<size_t>(filled), '#') +
         std::string(static_cast<size_t>(ProgressBar::kBarWidth - filled), '-') + tail;
}

ProgressBar::ProgressBar(std::string label, bool active, std::ostream& out)
    : label_(std::move(label)), active_(active), out_(out), start_(Clock::now()) {}

ProgressBar::ProgressBar(std::string label)
    : ProgressBar(std::move(label), ProgressOnStderr(), std::cerr) {}

ProgressBar::~ProgressBar() {
  if (drawn_ && !finished_) out_ << "\n" << std::flush;
}

void ProgressBar::Update(double fraction) { Update(fraction, Clock::now()); }

void ProgressBar::Update(double fraction, Clock::time_point now) {
  if (!active_) return;
  const std::lock_guard<std::mutex> lock(mutex_);
  if (finished_ || std::isnan(fraction)) return;
  fraction = std::clamp(fraction, 0.0, 1.0);
  if (fraction < shown_) return;
  shown_ = fraction;
  const auto interval = std::chrono::milliseconds(1000 / kRedrawsPerSecond);
  if (drawn_ && now - last_draw_ < interval) return;
  Draw(fraction, now);
}

void ProgressBar::Finish() {
  if (!active_) return;
  const std::lock_guard<std::mutex> lock(mutex_);
  if (finished_) return;
  Draw(1.0, Clock::now());
  out_ << "\n" << std::flush;
  finished_ = true;
}

std::function<void(double)> ProgressBar::Callback() {
  if (!active_) return {};  // library calls skip an empty callback entirely
  return [this](double fraction) { Update(fraction); };
}

void ProgressBar::Draw(double fraction, Clock::time_point now) {
  const double seconds = std::chrono::duration<double>(now - start_).count();
  out_ << "\r" << ProgressLine(label_, fraction, seconds) << std::flush;
  drawn_ = true;
  last_draw_ = now;
}

}  // namespace tinbase::cli
