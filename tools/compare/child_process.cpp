// fork + exec + wait4 polling (child_process.h). The child gets its own process group
// so that a kill at the time limit also reaches anything it started.
#include "child_process.h"

#include <pcl_vts/core/stopwatch.h>

#include <cerrno>
#include <chrono>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace pcl_vts {
namespace compare {

std::string selfExecutablePath()
{
  char buffer[PATH_MAX];
  const ssize_t length = ::readlink("/proc/self/exe", buffer, sizeof(buffer) - 1);
  if (length <= 0)
    return {};
  return std::string(buffer, static_cast<std::size_t>(length));
}

ChildOutcome runChild(const std::vector<std::string>& argv, double time_limit_seconds,
                      const std::string& log_path)
{
  ChildOutcome outcome;
  std::vector<char*> args;
  for (const std::string& arg : argv)
    args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  const int log = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  if (log < 0) {
    outcome.failure = "cannot open log " + log_path + ": " + std::strerror(errno);
    return outcome;
  }
  const Stopwatch watch;
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(log);
    outcome.failure = std::string("cannot start: fork: ") + std::strerror(errno);
    return outcome;
  }
  if (pid == 0) {
    ::setpgid(0, 0);
    // One thread per method: OpenMP (Open3D, PCL) would otherwise take every core.
    ::setenv("OMP_NUM_THREADS", "1", 1);
    ::dup2(log, STDOUT_FILENO);
    ::dup2(log, STDERR_FILENO);
    ::close(log);
    ::execv(args[0], args.data());
    const char* message = "compare_methods: exec failed\n";
    [[maybe_unused]] ssize_t ignored =
        ::write(STDERR_FILENO, message, std::strlen(message));
    ::_exit(127);
  }
  ::close(log);
  ::setpgid(pid, pid); // also here: no race with the kill below
  int status = 0;
  struct rusage usage {};
  for (;;) {
    const pid_t done = ::wait4(pid, &status, WNOHANG, &usage);
    if (done == pid)
      break;
    const double elapsed = watch.seconds();
    if (done < 0 && errno != EINTR) {
      outcome.failure = std::string("wait4: ") + std::strerror(errno);
      return outcome;
    }
    if (elapsed > time_limit_seconds && !outcome.timed_out) {
      outcome.timed_out = true;
      ::kill(-pid, SIGKILL);
      ::kill(pid, SIGKILL);
      continue;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(outcome.timed_out ? 1 : 10));
  }
  outcome.wall_seconds = watch.seconds();
  outcome.peak_rss_kib = usage.ru_maxrss;
  if (outcome.timed_out) {
    char text[64];
    std::snprintf(text, sizeof(text), "timed out after %g s", time_limit_seconds);
    outcome.failure = text;
  } else if (WIFSIGNALED(status)) {
    outcome.signal = WTERMSIG(status);
    outcome.failure = "killed by signal " + std::to_string(outcome.signal) + " (" +
                      ::strsignal(outcome.signal) + ")";
  } else if (WIFEXITED(status)) {
    outcome.exit_code = WEXITSTATUS(status);
    outcome.finished = outcome.exit_code == 0;
    if (!outcome.finished)
      outcome.failure = "exit status " + std::to_string(outcome.exit_code);
  }
  return outcome;
}

} // namespace compare
} // namespace pcl_vts
