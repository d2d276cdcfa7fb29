#include "util/timer.h"

#include <fmt/format.h>

namespace pluvia {

void StageTimes::add(const std::string& stage, double seconds) {
  std::lock_guard lock(mutex_);
  auto& entry = totals_[stage];
  entry.first += seconds;
  entry.second += 1;
}

std::map<std::string, std::pair<double, int>> StageTimes::snapshot() const {
  std::lock_guard lock(mutex_);
  return totals_;
}

std::string StageTimes::summary(int frames) const {
  auto totals = snapshot();
  std::string text = fmt::format("{:<14} {:>10} {:>12}\n", "stage", "total s", "ms/frame");
  for (const auto& [stage, entry] : totals) {
    text += fmt::format("{:<14} {:>10.3f} {:>12.2f}\n", stage, entry.first,
                        frames > 0 ? 1000.0 * entry.first / frames : 0.0);
  }
  return text;
}

ScopedTimer::~ScopedTimer() {
  if (times_) times_->add(stage_, secondsSince(start_));
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace pluvia
