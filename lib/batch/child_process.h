// Running one batch item as a child process: its arguments, limits and where its stderr
// goes, and what became of it.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

namespace ffd {

/// A running child.
struct Child {
  pid_t pid = -1;
  std::chrono::steady_clock::time_point started;
};

/// Starts `program` with `arguments` (argv[1..]), stdout to /dev/null and stderr to
/// `stderr_path`, its address space limited to `max_memory` bytes (0: no limit).
/// \throw IoError if it cannot be started.
Child start_child(const std::string& program, const std::vector<std::string>& arguments,
                  const std::string& stderr_path, std::size_t max_memory);

/// How a child ended.
struct ChildEnd {
  int exit = 0;         // 0, 2 or 3: ffdtool's exit code; 3 when anything else ended it
  std::string reason;   // for a signal, a timeout or a foreign exit code: what happened, else ""
};

/// The end of a child from waitpid's status, `timed_out` if we killed it for its time.
ChildEnd child_end(int status, bool timed_out, double timeout_s);

}  // namespace ffd
