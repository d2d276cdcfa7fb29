#include "util/progress.h"

#include <cmath>

#include <fmt/format.h>

#include "util/log.h"

namespace pluvia {

std::string etaText(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "ETA ?";
  const int64_t s = std::llround(seconds);
  if (s < 60) return fmt::format("ETA {} s", s);
  if (s < 3600) return fmt::format("ETA {} min {:02} s", s / 60, s % 60);
  return fmt::format("ETA {} h {:02} min", s / 3600, s / 60 % 60);
}

Progress::Progress(int total, bool enabled)
    : total_(total), enabled_(enabled), started_(std::chrono::steady_clock::now()) {}

void Progress::step(int64_t frame) {
  std::lock_guard lock(mutex_);
  ++done_;
  if (!enabled_) return;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  const double remaining = elapsed / done_ * (total_ - done_);
  const int percent = total_ > 0 ? 100 * done_ / total_ : 100;
  const std::string text =
      fmt::format("frame {} ({}/{}, {} %, {})", frame, done_, total_, percent, etaText(remaining));
  constexpr int kBarWidth = 30;
  const int filled = total_ > 0 ? kBarWidth * done_ / total_ : kBarWidth;
  const std::string bar = fmt::format("[{}{}] ", std::string(static_cast<size_t>(filled), '#'),
                                      std::string(static_cast<size_t>(kBarWidth - filled), '.'));
  log::progress("progress: " + text, bar + text, done_ == total_);
}

void Progress::finish() {
  std::lock_guard lock(mutex_);
  if (enabled_ && done_ > 0 && done_ < total_) log::progress("", "", true);
}

}  // namespace pluvia
