#include "batch/child_process.h"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "common/errors.h"

namespace ffd {

Child start_child(const std::string& program, const std::vector<std::string>& arguments,
                  const std::string& stderr_path, std::size_t max_memory) {
  std::vector<std::string> args;
  args.push_back(program);
  args.insert(args.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const int err = ::open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (err < 0) throw IoError(At{stderr_path}, std::string("cannot create: ") + std::strerror(errno));
  Child child;
  child.started = std::chrono::steady_clock::now();
  child.pid = ::fork();
  if (child.pid < 0) {
    ::close(err);
    throw IoError(std::string("cannot start a process: ") + std::strerror(errno));
  }
  if (child.pid == 0) {  // only async-signal-safe calls from here to exec
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) ::dup2(null, 1);
    ::dup2(err, 2);
    if (max_memory > 0) {
      const rlimit limit{static_cast<rlim_t>(max_memory), static_cast<rlim_t>(max_memory)};
      ::setrlimit(RLIMIT_AS, &limit);
    }
    ::execv(program.c_str(), argv.data());
    const char message[] = "ffdtool: error: cannot run the batch's item process\n";
    (void)!::write(2, message, sizeof message - 1);
    ::_exit(3);
  }
  ::close(err);
  return child;
}

ChildEnd child_end(int status, bool timed_out, double timeout_s) {
  if (timed_out) {
    char text[64];
    std::snprintf(text, sizeof text, "timed out after %g s", timeout_s);
    return {3, text};
  }
  if (WIFEXITED(status)) {
    const int code = WEXITSTATUS(status);
    if (code == 0 || code == 2 || code == 3) return {code, ""};
    return {3, "exited with code " + std::to_string(code)};  // not ffdtool's: it could not start
  }
  if (WIFSIGNALED(status)) {
    const int signal = WTERMSIG(status);
    const char* name = ::strsignal(signal);
    return {3, "killed by signal " + std::to_string(signal) + " (" + (name ? name : "?") + ")"};
  }
  return {3, "ended in an unknown way"};
}

}  // namespace ffd
