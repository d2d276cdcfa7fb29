#pragma once
// Per-stage wall-clock timing for --stats and `pluvia bench`. Thread-safe accumulation.
#include <chrono>
#include <map>
#include <mutex>
#include <string>

namespace pluvia {

class StageTimes {
 public:
  void add(const std::string& stage, double seconds);
  // Stage -> (total seconds, calls), in insertion-independent (sorted) order.
  std::map<std::string, std::pair<double, int>> snapshot() const;
  std::string summary(int frames) const;  // a small table, one line a stage

 private:
  mutable std::mutex mutex_;
  std::map<std::string, std::pair<double, int>> totals_;
};

// Adds the scope's duration to `times` under `stage` when it ends.
class ScopedTimer {
 public:
  ScopedTimer(StageTimes* times, std::string stage)
      : times_(times), stage_(std::move(stage)), start_(std::chrono::steady_clock::now()) {}
  ~ScopedTimer();
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  StageTimes* times_;
  std::string stage_;
  std::chrono::steady_clock::time_point start_;
};

double secondsSince(std::chrono::steady_clock::time_point start);

}  // namespace pluvia
