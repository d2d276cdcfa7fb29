#pragma once
// A child process whose standard output we read (ffmpeg decoding frames to raw RGB). Its
// standard error goes to an unlinked temporary file, read back by errorText(): a pipe left
// unread there could fill and stall the child on a file that makes it complain at length.
#include <string>
#include <vector>

namespace pluvia {

class ReadPipe {
 public:
  // Starts argv[0] (searched on PATH, no shell) in its own process group. Throws pluvia::Error
  // when it cannot be started.
  explicit ReadPipe(const std::vector<std::string>& argv);
  // Stops the child (SIGTERM) when it is still running, and waits for it.
  ~ReadPipe();
  ReadPipe(const ReadPipe&) = delete;
  ReadPipe& operator=(const ReadPipe&) = delete;

  // Reads exactly `bytes` bytes; false when the output ends first (a short read is dropped).
  bool readExactly(void* data, size_t bytes);
  // Reads and throws away `bytes` bytes; false when the output ends first.
  bool skip(size_t bytes);
  // The last `maxLines` lines the child wrote to standard error, each on its own line
  // indented by two spaces; "" when it wrote nothing.
  std::string errorText(int maxLines = 8) const;

 private:
  int pid_ = -1;
  int stdoutFd_ = -1;
  int stderrFd_ = -1;
};

}  // namespace pluvia
