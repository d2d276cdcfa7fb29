#include "util/progress.h"

#include <unistd.h>

namespace pluvia {

Progress::Progress(int total, bool enabled)
    : total_(total), enabled_(enabled), terminal_(isatty(fileno(stderr)) != 0) {}

void Progress::step() {
  std::lock_guard lock(mutex_);
  ++done_;
  if (!enabled_) return;
  if (terminal_) {
    const int width = 40;
    int filled = total_ > 0 ? width * done_ / total_ : width;
    std::fprintf(stderr, "\r[");
    for (int i = 0; i < width; ++i) std::fputc(i < filled ? '#' : '.', stderr);
    std::fprintf(stderr, "] %d/%d", done_, total_);
  } else {
    std::fprintf(stderr, "progress: %d/%d\n", done_, total_);
  }
  std::fflush(stderr);
}

void Progress::finish() {
  std::lock_guard lock(mutex_);
  if (enabled_ && terminal_) std::fprintf(stderr, "\n");
}

}  // namespace pluvia
