#pragma once
// Running an external program (ffmpeg, colmap) without a shell: arguments are passed as-is.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "util/interrupt.h"

namespace pluvia {

struct ProcessResult {
  int exitCode = -1;
  std::string output;  // stdout and stderr together
};

// Runs argv[0] with the arguments, waits, and returns its exit code and output.
ProcessResult runProcess(const std::vector<std::string>& argv);

// A child process whose standard input we write to (ffmpeg encoding raw frames).
class PipeProcess {
 public:
  explicit PipeProcess(const std::vector<std::string>& argv, const std::string& logPath);
  ~PipeProcess();
  PipeProcess(const PipeProcess&) = delete;
  PipeProcess& operator=(const PipeProcess&) = delete;
  void write(const void* data, size_t bytes);
  int close();  // closes stdin, waits, returns the exit code

 private:
  int pid_ = -1;
  int stdinFd_ = -1;
  // Killed if a second signal stops pluvia at once (util/interrupt.h), until it is reaped.
  std::unique_ptr<KilledOnHardStop> killedOnHardStop_;
};

// True when `program` is an executable file: found on PATH, or at the path given when it holds
// a '/'. No shell is involved.
bool programAvailable(const std::string& program);

}  // namespace pluvia
