#pragma once
// Runs the `nsf` executable as a child process the test controls: under a resource limit, or
// left running so that the test can signal it. Its stdout and stderr go to a log file.
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <cerrno>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace nsf::testing {

// Starts NSF_CLI with `args`; `in_child` runs in the child before exec (async-signal-safe calls
// only: setrlimit, signal). Returns the child's pid, or -1.
inline pid_t spawn_cli(const std::vector<std::string>& args, const std::string& log,
                       const std::function<void()>& in_child = {}) {
  std::vector<std::string> argv{NSF_CLI};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> ptrs;
  for (std::string& a : argv) ptrs.push_back(a.data());
  ptrs.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd >= 0) {
    ::dup2(fd, STDOUT_FILENO);
    ::dup2(fd, STDERR_FILENO);
    ::close(fd);
  }
  // The signals the tests send reach nsf as from a terminal, even where the test runner was
  // started with them ignored (a background job of a non-interactive shell ignores SIGINT, and
  // nsf keeps an ignored signal ignored).
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) ::signal(sig, SIG_DFL);
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
  if (in_child) in_child();
  ::execv(ptrs[0], ptrs.data());
  ::_exit(127);
}

// Waits for `pid` and returns its raw wait status (WIFEXITED, WIFSIGNALED, ...), or -1.
inline int wait_child(pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  return status;
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace nsf::testing
