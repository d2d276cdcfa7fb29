#pragma once
// One cap on the threads of every pool in the process (`--threads`): TBB's (the derain solver,
// the environment maps, OpenCV's parallel loops run on it), pluvia's own bands (colour
// conversion), and the ffmpeg and OpenImageIO workers that read threadLimit().
#include <memory>

namespace pluvia {

// The cap now: the last ThreadLimit's, else the hardware's thread count.
int threadLimit();

// Holds the cap for its lifetime (one at a time; the previous cap comes back afterwards).
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pluvia
