#pragma once
// One render at a time into each frame of an output. Two renders with different seeds into one
// folder used to interleave their frames; now the second is refused. Farm chunks render
// disjoint frame ranges of one output at the same time: each locks only its frames.
#include <cstdint>
#include <string>

#include "io/output_target.h"
#include "util/file_lock.h"

namespace pluvia {

// The lock file for an output: beside it, named after the frames it guards, whatever the
// pattern's spelling ("out.####.exr" and "out.%04d.exr" -> "out.####.exr.pluvia-lock"; a movie
// or one image: "rain.mp4" -> "rain.mp4.pluvia-lock").
std::string outputLockPath(const OutputTarget& output);

// Holds frames firstFrame..lastFrame of a sequence output (a movie or one image: all of it) for
// its lifetime, as a byte range of the output's lock file (util/file_lock.h: the kernel drops it
// when the render dies, so a killed render's lock holds nothing). The last holder removes the
// lock file.
class OutputLock {
 public:
  // Creates the output folder when needed. Throws pluvia::Error naming the other render's pid,
  // host and frames when it holds any of these frames.
  OutputLock(const OutputTarget& output, int64_t firstFrame, int64_t lastFrame);
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  // Removes the temporaries that renders killed by SIGKILL or a crash left (their pid runs no
  // process here): for a sequence, only those of the frames this lock holds, since a chunk on
  // another host, whose pid means nothing here, may be writing other frames of the output.
  // Returns the count.
  int removeStaleTemporaries() const;

 private:
  OutputTarget output_;
  int64_t firstFrame_, lastFrame_;
  bool wholeOutput_;
  FileRangeLock lock_;
};

}  // namespace pluvia
