#pragma once
// Starting other programs (gnuplot, ffmpeg) without a shell. A command line put together as text
// and handed to /bin/sh turns every quote, `;` or `$(...)` in a file name or scene name into
// shell syntax; an argument vector passes each argument to the program exactly as it is.
#include <string>
#include <vector>

namespace nsf {

// Runs argv[0] (looked up on PATH unless it contains a '/') with the arguments argv[1..] and
// waits for it. Its stdin is /dev/null, so it can neither wait for nor eat the terminal's input.
// With `stdout_stderr_file`, both of its output streams go to that file (created or truncated);
// without, it shares ours. Returns its exit status, 128 + the signal number if a signal ended it,
// or -1 if it could not be started (no such program, argv empty, the file cannot be opened).
int run_program(const std::vector<std::string>& argv, const std::string& stdout_stderr_file = "");

// Full path of the executable `name` on PATH (or `name` itself when it contains a '/' and is
// executable); "" when there is none.
std::string find_on_path(const std::string& name);

// Whether run_program({name, ...}) would find `name`.
bool program_exists(const std::string& name);

}  // namespace nsf
