#pragma once
// The exit status of every `nsf` command (README, "Command-line conventions"; `nsf --help`).
// A process ended by a signal (Ctrl-C, SIGTERM, SIGHUP) dies of it after deleting its temporary
// files: the shell then reports 128 + the signal's number (130 for Ctrl-C).

namespace nsf::app {

enum ExitCode : int {
  kExitSuccess = 0,
  kExitError = 1,     // the command line was fine, the work failed: a missing, malformed or
                      // damaged input, a full disk, a simulation that blew up (`nsf: error: `)
  kExitUsage = 2,     // the command line itself: an unknown option, a missing argument, a value
                      // out of range or not among the choices (`nsf: usage error: `)
  kExitInternal = 3,  // a bug in nsf: an exception nsf did not expect (`nsf: internal error: `)
};

// The text `nsf --help` ends with.
inline const char* exit_status_help() {
  return "Exit status: 0 success; 1 error (a missing, malformed or damaged input, a full disk, "
         "a failed run); 2 usage error (unknown option, missing argument, bad value); 3 internal "
         "error (a bug: please report it); 128+N killed by signal N (130: Ctrl-C).\n"
         "Every command: -j/--threads N threads (default: all cores), -q/--quiet no progress "
         "lines; `nsf COMMAND --help` lists the rest.";
}

}  // namespace nsf::app
