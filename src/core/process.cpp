#include "core/process.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <system_error>

extern char** environ;

namespace nsf {

namespace fs = std::filesystem;

namespace {

bool is_executable_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec) && ::access(p.c_str(), X_OK) == 0;
}

// posix_spawn's file actions, released on every path out of run_program.
class FileActions {
 public:
  FileActions() { ok_ = posix_spawn_file_actions_init(&fa_) == 0; }
  ~FileActions() {
    if (ok_) posix_spawn_file_actions_destroy(&fa_);
  }
  FileActions(const FileActions&) = delete;
  FileActions& operator=(const FileActions&) = delete;
  bool ok() const { return ok_; }
  posix_spawn_file_actions_t* get() { return &fa_; }

 private:
  posix_spawn_file_actions_t fa_;
  bool ok_ = false;
};

}  // namespace

int run_program(const std::vector<std::string>& argv, const std::string& stdout_stderr_file) {
  if (argv.empty() || argv[0].empty()) return -1;
  FileActions actions;
  if (!actions.ok()) return -1;
  posix_spawn_file_actions_t* fa = actions.get();
  if (posix_spawn_file_actions_addopen(fa, STDIN_FILENO, "/dev/null", O_RDONLY, 0) != 0) return -1;
  if (!stdout_stderr_file.empty()) {
    // The path is copied by addopen; the child opens it, so an unopenable file fails the spawn.
    if (posix_spawn_file_actions_addopen(fa, STDOUT_FILENO, stdout_stderr_file.c_str(),
                                         O_WRONLY | O_CREAT | O_TRUNC, 0644) != 0 ||
        posix_spawn_file_actions_adddup2(fa, STDOUT_FILENO, STDERR_FILENO) != 0)
      return -1;
  }
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);

  pid_t pid = 0;
  if (posix_spawnp(&pid, args[0], fa, nullptr, args.data(), environ) != 0) return -1;
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

std::string find_on_path(const std::string& name) {
  if (name.empty()) return "";
  // Like execvp: a name with a slash is a path, not something to look up.
  if (name.find('/') != std::string::npos) return is_executable_file(name) ? name : "";
  const char* path = std::getenv("PATH");
  if (!path) return "";
  std::istringstream dirs(path);
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    if (dir.empty()) dir = ".";
    const fs::path p = fs::path(dir) / name;
    if (is_executable_file(p)) return p.string();
  }
  return "";
}

bool program_exists(const std::string& name) {
  return !find_on_path(name).empty();
}

}  // namespace nsf
