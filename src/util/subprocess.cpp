#include "util/subprocess.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "util/error.h"

namespace pluvia {
namespace {

std::vector<char*> makeArgv(const std::vector<std::string>& argv) {
  std::vector<char*> out;
  for (const auto& a : argv) out.push_back(const_cast<char*>(a.c_str()));
  out.push_back(nullptr);
  return out;
}

int waitExit(int pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

}  // namespace

// Every pipe is made close-on-exec: a child must not keep another child's pipe ends. An
// encoder's stdin write end held open by a decoder started after it (a movie in, a movie out)
// keeps the encoder from ever seeing the end of its input, and the render hangs at close().
ProcessResult runProcess(const std::vector<std::string>& argv) {
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) throw Error("cannot create a pipe to run " + argv.at(0));
  int pid = fork();
  if (pid < 0) throw Error("cannot start " + argv.at(0));
  if (pid == 0) {
    dup2(fds[1], 1);
    dup2(fds[1], 2);
    close(fds[0]);
    close(fds[1]);
    int devnull = open("/dev/null", O_RDONLY);
    if (devnull >= 0) dup2(devnull, 0);
    auto args = makeArgv(argv);
    execvp(args[0], args.data());
    _exit(127);
  }
  close(fds[1]);
  ProcessResult result;
  char buffer[4096];
  ssize_t n;
  while ((n = read(fds[0], buffer, sizeof buffer)) > 0 || (n < 0 && errno == EINTR)) {
    if (n > 0) result.output.append(buffer, static_cast<size_t>(n));
  }
  close(fds[0]);
  result.exitCode = waitExit(pid);
  return result;
}

PipeProcess::PipeProcess(const std::vector<std::string>& argv, const std::string& logPath) {
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) throw Error("cannot create a pipe to run " + argv.at(0));
  pid_ = fork();
  if (pid_ < 0) throw Error("cannot start " + argv.at(0));
  if (pid_ == 0) {
    // Its own process group: a Ctrl-C reaches only pluvia, which stops the encoder itself and
    // removes what it wrote.
    setpgid(0, 0);
    dup2(fds[0], 0);
    ::close(fds[0]);
    ::close(fds[1]);
    int log = open(logPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (log >= 0) {
      dup2(log, 1);
      dup2(log, 2);
    }
    auto args = makeArgv(argv);
    execvp(args[0], args.data());
    _exit(127);
  }
  ::close(fds[0]);
  stdinFd_ = fds[1];
  killedOnHardStop_ = std::make_unique<KilledOnHardStop>(pid_);
  // A dead encoder must give an error, not kill us with SIGPIPE.
  signal(SIGPIPE, SIG_IGN);
}

PipeProcess::~PipeProcess() {
  if (pid_ > 0) {
    if (stdinFd_ >= 0) ::close(stdinFd_);
    kill(pid_, SIGTERM);
    waitExit(pid_);
    killedOnHardStop_.reset();
  }
}

void PipeProcess::write(const void* data, size_t bytes) {
  const char* p = static_cast<const char*>(data);
  while (bytes > 0) {
    ssize_t n = ::write(stdinFd_, p, bytes);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw Error(std::string("the encoder stopped accepting frames: ") + std::strerror(errno));
    }
    p += n;
    bytes -= static_cast<size_t>(n);
  }
}

int PipeProcess::close() {
  if (stdinFd_ >= 0) ::close(stdinFd_);
  stdinFd_ = -1;
  int code = waitExit(pid_);
  killedOnHardStop_.reset();
  pid_ = -1;
  return code;
}

bool programAvailable(const std::string& program) {
  // Searched here, as execvp() would, never through a shell: the name may come from the
  // environment ($PLUVIA_COLMAP) and must not run as a command line.
  auto executable = [](const std::string& path) {
    struct stat info {};
    return ::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode) &&
           ::access(path.c_str(), X_OK) == 0;
  };
  if (program.empty()) return false;
  if (program.find('/') != std::string::npos) return executable(program);
  const char* path = std::getenv("PATH");
  const std::string folders = path ? path : "/usr/local/bin:/usr/bin:/bin";
  for (size_t start = 0; start <= folders.size();) {
    const size_t colon = std::min(folders.find(':', start), folders.size());
    const std::string folder = folders.substr(start, colon - start);
    if (executable((folder.empty() ? "." : folder) + "/" + program)) return true;
    start = colon + 1;
  }
  return false;
}

}  // namespace pluvia
