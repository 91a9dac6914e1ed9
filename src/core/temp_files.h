#pragma once
// Temp files ("<out>.tmp") that must not outlive an interrupted command. Every writer that
// produces <out>.tmp and renames it into place registers it for as long as it exists; Ctrl-C
// (SIGINT), SIGTERM or SIGHUP then deletes every registered file before the process dies of the
// signal as it would have without nsf (the default action, re-raised). The handlers are installed
// with the first registration, and only for signals whose disposition is still the default, so a
// host program's own handlers and `nohup`'s ignored SIGHUP are left alone. SIGKILL and a crash
// cannot be caught: the next write of the same output truncates its stale .tmp.
#include <string>

namespace nsf {

class TempFileRegistration {
 public:
  TempFileRegistration() = default;
  explicit TempFileRegistration(const std::string& path);  // made absolute
  ~TempFileRegistration() { release(); }
  TempFileRegistration(TempFileRegistration&& o) noexcept;
  TempFileRegistration& operator=(TempFileRegistration&& o) noexcept;
  TempFileRegistration(const TempFileRegistration&) = delete;
  TempFileRegistration& operator=(const TempFileRegistration&) = delete;

  // Stops tracking the file (it has been renamed or removed). Idempotent.
  void release();

 private:
  int slot_ = -1;  // -1: not registered (none taken, all slots busy, or a path too long)
};

// How many temp files are registered now (for tests).
int registered_temp_files();

}  // namespace nsf
