// Child processes measured on their own: wall time and peak resident set.
//
// wait4's ru_maxrss of a child also counts the process it started from: exec keeps the
// high-water mark of the address space it replaces, and a child made by fork or
// posix_spawn starts in (a copy of) ours, which holds the benchmark's meshes. So a child
// runs under ffdbench itself in launcher mode (`ffdbench --launch RESULT PROGRAM
// ARGS...`), a fresh process of about 6 MB: it spawns PROGRAM, reaps it with wait4 and
// writes "wall_ms peak_bytes minor_faults" to RESULT. A child's peak below the launcher's
// size reads as the launcher's size.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace ffd::bench {

/// A finished child process: wall time from spawn to reaping, peak resident set, the page
/// faults it took that needed no I/O (pages of fresh memory among them: where faults are
/// dear, a large part of its time), its exit code and whether it was 0, and its stdout and
/// stderr.
struct ChildRun {
  double ms = 0;
  std::size_t peak_bytes = 0;
  long minor_faults = 0;
  int exit = 0;
  bool ok = false;
  std::string out, err;
};

/// Runs `argv` (argv[0] a path) through the launcher, with stdin from /dev/null and
/// stdout and stderr captured through files in `folder`.
/// \throw InputError if the launcher cannot be started.
ChildRun run_measured(const std::vector<std::string>& argv, const std::string& folder);

/// The launcher mode, for main() when argv[1] is "--launch": argv = ffdbench --launch
/// RESULT PROGRAM ARGS...; returns PROGRAM's exit status (128 + signal if killed, 127 if
/// it could not be started, 2 on bad usage).
int launch_main(int argc, char** argv);

}  // namespace ffd::bench
