#include "util/read_pipe.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <deque>

#include "util/error.h"

namespace pluvia {

ReadPipe::ReadPipe(const std::vector<std::string>& argv) {
  char errorTemplate[] = "/tmp/pluvia-pipe-XXXXXX";
  stderrFd_ = mkostemp(errorTemplate, O_CLOEXEC);
  if (stderrFd_ < 0) throw Error("cannot create a temporary file to run " + argv.at(0));
  unlink(errorTemplate);
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) throw Error("cannot create a pipe to run " + argv.at(0));
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  pid_ = fork();
  if (pid_ < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw Error("cannot start " + argv.at(0));
  }
  if (pid_ == 0) {
    // Its own process group: a Ctrl-C reaches only pluvia, which stops the child itself.
    setpgid(0, 0);
    dup2(fds[1], 1);
    dup2(stderrFd_, 2);
    ::close(fds[0]);
    ::close(fds[1]);
    const int devnull = open("/dev/null", O_RDONLY);
    if (devnull >= 0) dup2(devnull, 0);
    execvp(args[0], args.data());
    _exit(127);
  }
  ::close(fds[1]);
  stdoutFd_ = fds[0];
}

ReadPipe::~ReadPipe() {
  if (stdoutFd_ >= 0) ::close(stdoutFd_);
  if (pid_ > 0) {
    kill(pid_, SIGTERM);
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
  }
  if (stderrFd_ >= 0) ::close(stderrFd_);
}

bool ReadPipe::readExactly(void* data, size_t bytes) {
  char* p = static_cast<char*>(data);
  while (bytes > 0) {
    const ssize_t n = ::read(stdoutFd_, p, bytes);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    bytes -= static_cast<size_t>(n);
  }
  return true;
}

bool ReadPipe::skip(size_t bytes) {
  std::vector<char> sink(std::min<size_t>(bytes, 1 << 20));
  while (bytes > 0) {
    const size_t chunk = std::min(bytes, sink.size());
    if (!readExactly(sink.data(), chunk)) return false;
    bytes -= chunk;
  }
  return true;
}

std::string ReadPipe::errorText(int maxLines) const {
  std::string text;
  char buffer[4096];
  for (off_t offset = 0;;) {
    const ssize_t n = pread(stderrFd_, buffer, sizeof buffer, offset);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    text.append(buffer, static_cast<size_t>(n));
    offset += n;
  }
  std::deque<std::string> lines;
  for (size_t start = 0; start < text.size();) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    if (end > start) lines.push_back(text.substr(start, end - start));
    if (static_cast<int>(lines.size()) > maxLines) lines.pop_front();
    start = end + 1;
  }
  std::string out;
  for (const std::string& line : lines) out += "\n  " + line;
  return out;
}

}  // namespace pluvia
