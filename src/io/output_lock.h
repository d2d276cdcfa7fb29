#pragma once
// One render at a time into an output. Two renders with different seeds into one folder used to
// interleave their frames; now the second is refused.
#include <string>

namespace pluvia {

// The lock file for an output: beside it, named after the frames it guards, whatever the
// pattern's spelling ("out.####.exr" and "out.%04d.exr" -> "out.####.exr.pluvia-lock"; a movie
// or one image: "rain.mp4" -> "rain.mp4.pluvia-lock").
std::string outputLockPath(const std::string& output);

// Holds the output's lock file for its lifetime with flock(), writing "pid host" into it. The
// kernel drops an flock when its process dies, so a killed render's lock file holds nothing and
// the next render takes it over. Removed by the destructor.
class OutputLock {
 public:
  // Creates the output folder when needed. Throws pluvia::Error naming the other render's pid
  // and host when it holds the lock.
  explicit OutputLock(const std::string& output);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace pluvia
