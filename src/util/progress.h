#pragma once
// Progress of a render, one line a frame for farm logs and wranglers:
// "progress: frame 1005 (3/10, 30 %, ETA 12 s)"; on a terminal the same text after a bar,
// rewritten in place. Through util/log.h, so -q silences it and --log FILE records it.
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace pluvia {

// "ETA 12 s", "ETA 3 min 20 s", "ETA 1 h 02 min"; "ETA ?" before anything is known.
std::string etaText(double seconds);

class Progress {
 public:
  Progress(int total, bool enabled);
  void step(int64_t frame);  // frame `frame` is done; the last one ends the terminal's line
  void finish();             // ends a terminal line a stopped render left open

 private:
  int total_;
  int done_ = 0;
  bool enabled_;
  std::chrono::steady_clock::time_point started_;
  std::mutex mutex_;
};

}  // namespace pluvia
