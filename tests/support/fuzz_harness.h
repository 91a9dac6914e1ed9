#pragma once
// A small, seeded mutation fuzzer for the readers of files people pass around (scenes, model
// files): mutations of valid inputs, each fed to the reader in a forked child under a time limit,
// so that a crash, a hang or an exception other than nsf::Error is reported with the case that
// caused it instead of taking the test binary down. The seed comes from NSF_FUZZ_SEED (default a
// fixed one), the case count from NSF_FUZZ_CASES; a failing case is written to a file and its
// seed, index and replay command are printed.
#include <gtest/gtest.h>
#include <omp.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <system_error>
#include <vector>

#include "core/error.h"

namespace nsf::testing::fuzz {

// The run's seed: NSF_FUZZ_SEED, or `fallback`, so CI runs the same cases every time and a
// failure replays with the printed seed.
inline uint64_t seed(uint64_t fallback) {
  const char* s = std::getenv("NSF_FUZZ_SEED");
  return s && *s ? std::strtoull(s, nullptr, 0) : fallback;
}

// NSF_FUZZ_CASES, or `fallback`.
inline int case_count(int fallback) {
  const char* s = std::getenv("NSF_FUZZ_CASES");
  return s && *s ? std::atoi(s) : fallback;
}

// How one case ended.
enum class Outcome { Accepted, NamedError, OtherException, Crashed, TimedOut };

inline const char* outcome_name(Outcome o) {
  switch (o) {
    case Outcome::Accepted:
      return "accepted";
    case Outcome::NamedError:
      return "nsf::Error";
    case Outcome::OtherException:
      return "an exception other than nsf::Error";
    case Outcome::Crashed:
      return "a crash";
    case Outcome::TimedOut:
      return "a hang (time limit)";
  }
  return "?";
}

struct Result {
  Outcome outcome;
  std::string detail;  // the exception's message, or the signal / exit status
};

// Runs `fn` in a forked child with one thread and `seconds` of wall time. Accepted when it
// returns, NamedError when it throws nsf::Error, OtherException for any other exception, Crashed
// when the child dies of a signal or exits abnormally (a sanitizer's report), TimedOut when it
// runs past the limit (then it is killed).
inline Result run_bounded(const std::function<void()>& fn, double seconds) {
  int fds[2];
  if (::pipe(fds) != 0) return {Outcome::Crashed, "pipe failed"};
  const pid_t pid = ::fork();
  if (pid < 0) return {Outcome::Crashed, "fork failed"};
  if (pid == 0) {
    ::close(fds[0]);
    omp_set_num_threads(1);  // the parent's OpenMP threads do not exist in the child
    const rlimit no_core{0, 0};
    ::setrlimit(RLIMIT_CORE, &no_core);  // a crash is reported, not dumped
    char kind = 'A';
    std::string msg;
    try {
      fn();
    } catch (const Error& e) {
      kind = 'N';
      msg = e.what();
    } catch (const std::exception& e) {
      kind = 'O';
      msg = e.what();
    } catch (...) {
      kind = 'O';
      msg = "(not a std::exception)";
    }
    msg.insert(msg.begin(), kind);
    for (size_t at = 0; at < msg.size();) {
      const ssize_t n = ::write(fds[1], msg.data() + at, msg.size() - at);
      if (n <= 0) break;
      at += static_cast<size_t>(n);
    }
    ::_exit(0);  // no atexit handlers, no gtest teardown in the child
  }
  ::close(fds[1]);
  std::string msg;
  bool timed_out = false;
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::milliseconds(long(seconds * 1000));
  for (;;) {
    const long left = std::chrono::duration_cast<std::chrono::milliseconds>(
                          deadline - std::chrono::steady_clock::now())
                          .count();
    if (left <= 0) {
      timed_out = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int r = ::poll(&p, 1, static_cast<int>(left));
    if (r < 0 && errno == EINTR) continue;
    if (r == 0) continue;  // the deadline check above ends the loop
    char buf[4096];
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // the child closed the pipe: it finished or died
    msg.append(buf, static_cast<size_t>(n));
  }
  ::close(fds[0]);
  if (timed_out) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (timed_out)
    return {Outcome::TimedOut, "still running after " + std::to_string(seconds) + " s"};
  if (WIFSIGNALED(status))
    return {Outcome::Crashed, std::string("signal ") + strsignal(WTERMSIG(status))};
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || msg.empty())
    return {Outcome::Crashed, "exit status " + std::to_string(WEXITSTATUS(status))};
  const std::string detail = msg.substr(1);
  if (msg[0] == 'A') return {Outcome::Accepted, detail};
  if (msg[0] == 'N') return {Outcome::NamedError, detail};
  return {Outcome::OtherException, detail};
}

// Byte-level mutations of a text or binary file.
class ByteMutator {
 public:
  explicit ByteMutator(std::mt19937_64& rng) : rng_(rng) {}

  size_t below(size_t n) {
    return n == 0 ? 0 : std::uniform_int_distribution<size_t>(0, n - 1)(rng_);
  }

  // One of: flip a bit, set a byte, truncate, delete a range, duplicate a range, insert random
  // bytes, zero a range. `what` says which (for the failure report).
  std::string mutate(std::string b, std::string& what) {
    const size_t n = b.size();
    switch (below(7)) {
      case 0: {
        const size_t at = below(n);
        if (n) b[at] = static_cast<char>(b[at] ^ (1 << below(8)));
        what = "bit flip at " + std::to_string(at);
        break;
      }
      case 1: {
        const size_t at = below(n);
        const char interesting[] = {0, '\xff', '"', '{', '[', ']', '}', ',', ':', '\\', '-', '9'};
        if (n) b[at] = interesting[below(sizeof interesting)];
        what = "byte set at " + std::to_string(at);
        break;
      }
      case 2: {
        const size_t keep = below(n);
        b.resize(keep);
        what = "truncated to " + std::to_string(keep);
        break;
      }
      case 3: {
        const size_t at = below(n), len = std::min(n - at, 1 + below(64));
        if (n) b.erase(at, len);
        what = "deleted " + std::to_string(len) + " at " + std::to_string(at);
        break;
      }
      case 4: {
        const size_t at = below(n), len = std::min(n - at, 1 + below(256));
        if (n) b.insert(at, b.substr(at, len));
        what = "duplicated " + std::to_string(len) + " at " + std::to_string(at);
        break;
      }
      case 5: {
        const size_t at = below(n + 1), len = 1 + below(16);
        std::string r(len, '\0');
        for (char& c : r) c = static_cast<char>(below(256));
        b.insert(at, r);
        what = "inserted " + std::to_string(len) + " random bytes at " + std::to_string(at);
        break;
      }
      default: {
        const size_t at = below(n), len = std::min(n - at, 1 + below(512));
        if (n) std::fill(b.begin() + at, b.begin() + at + len, '\0');
        what = "zeroed " + std::to_string(len) + " at " + std::to_string(at);
        break;
      }
    }
    return b;
  }

 private:
  std::mt19937_64& rng_;
};

// Tallies outcomes and reports the cases that broke the contract: accepted, or an nsf::Error with
// a message that is not an "internal error".
struct Tally {
  int accepted = 0, named = 0;
  std::vector<std::string> failures;

  void add(const Result& r, const std::string& case_description) {
    if (r.outcome == Outcome::Accepted) {
      ++accepted;
    } else if (r.outcome == Outcome::NamedError && !r.detail.empty() &&
               r.detail.find("internal error") == std::string::npos) {
      ++named;
    } else if (r.outcome == Outcome::NamedError) {
      failures.push_back(case_description + ": an nsf::Error that names nothing: " + r.detail);
    } else {
      failures.push_back(case_description + ": " + outcome_name(r.outcome) + ": " + r.detail);
    }
  }

  // The run's summary line; each failure fails the test with the seed that replays it. The
  // cases' folder is removed when nothing failed (a failing case's file is kept to replay).
  void report(uint64_t seed, const std::string& dir) const {
    std::printf("fuzz: %d accepted, %d refused with a named error, %zu failures\n", accepted, named,
                failures.size());
    for (const std::string& f : failures) ADD_FAILURE() << f << "\nreplay: NSF_FUZZ_SEED=" << seed;
    if (failures.empty()) {
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
    EXPECT_GT(named, 0);
  }
};

}  // namespace nsf::testing::fuzz
