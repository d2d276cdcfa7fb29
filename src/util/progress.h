#pragma once
// Progress reporting: a bar on a terminal, "progress: N/M" lines otherwise (farm logs).
#include <cstdio>
#include <mutex>

namespace pluvia {

class Progress {
 public:
  Progress(int total, bool enabled);
  void step();  // one more frame done
  void finish();

 private:
  int total_;
  int done_ = 0;
  bool enabled_;
  bool terminal_;
  std::mutex mutex_;
};

}  // namespace pluvia
