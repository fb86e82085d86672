// Child processes measured on their own (child_run.h says why through a launcher).
#include "child_run.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/errors.h"
#include "common/timer.h"

extern char** environ;

namespace ffd::bench {
namespace {

namespace fs = std::filesystem;

/// Reaps `pid` with wait4, retrying on EINTR; returns its status and fills `usage`.
int reap(pid_t pid, rusage& usage) {
  int status = 0;
  while (::wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
  }
  return status;
}

/// The exit code a shell would report for wait status `status`.
int exit_code(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 1;
}

/// The whole text of a small file (empty if it cannot be read).
std::string slurp(const fs::path& path) {
  std::ifstream is(path, std::ios::binary);
  std::ostringstream ss;
  ss << is.rdbuf();
  return ss.str();
}

/// This executable's path, for the launcher.
std::string self_path() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw InputError("/proc/self/exe: cannot read: " + ec.message());
  return self.string();
}

}  // namespace

int launch_main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: ffdbench --launch RESULT PROGRAM [ARGS...]\n");
    return 2;
  }
  Stopwatch clock;
  pid_t pid = 0;
  const int started = posix_spawn(&pid, argv[3], nullptr, nullptr, argv + 3, environ);
  if (started != 0) {
    std::fprintf(stderr, "ffdbench: cannot run %s: %s\n", argv[3], std::strerror(started));
    return 127;
  }
  rusage usage{};
  const int status = reap(pid, usage);
  const double ms = clock.ms();
  if (std::FILE* f = std::fopen(argv[2], "w")) {
    std::fprintf(f, "%.6f %zu %ld\n", ms, static_cast<std::size_t>(usage.ru_maxrss) * 1024, usage.ru_minflt);
    std::fclose(f);
  }
  return exit_code(status);
}

ChildRun run_measured(const std::vector<std::string>& argv, const std::string& folder) {
  const fs::path dir(folder);
  const std::string result = (dir / "child.result").string(), out = (dir / "child.out").string(),
                    err = (dir / "child.err").string();
  std::vector<std::string> full = {self_path(), "--launch", result};
  full.insert(full.end(), argv.begin(), argv.end());
  std::vector<char*> args;
  for (const std::string& a : full) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::remove(result.c_str());
  pid_t pid = 0;
  const int started = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (started != 0) throw InputError(full[0] + ": cannot run: " + std::strerror(started));
  rusage usage{};
  const int status = reap(pid, usage);
  ChildRun run;
  std::istringstream measured(slurp(result));
  // Measured whatever the exit: compare exits 1 for a difference, batch for a failed mesh.
  const bool measured_ok = static_cast<bool>(measured >> run.ms >> run.peak_bytes >> run.minor_faults);
  run.exit = exit_code(status);
  run.ok = run.exit == 0 && measured_ok;
  run.out = slurp(out);
  run.err = slurp(err);
  return run;
}

}  // namespace ffd::bench
