// Runs a command line and kills it (SIGKILL: no handler, no cleanup) after
// a given time, as a power cut or an impatient user would.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

namespace bead::test {

// The command's exit status when it ended within `delay_s`, else -1 (killed).
inline int RunKilledAfter(const std::string& command, double delay_s) {
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string line = "exec " + command + " >/dev/null 2>&1";
    execl("/bin/sh", "sh", "-c", line.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(delay_s);
  int status = 0;
  while (std::chrono::steady_clock::now() < end) {
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -2;
    std::this_thread::sleep_for(std::chrono::microseconds(500));
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Seconds a command takes, run to its end; `status` gets its exit status.
inline double TimeCommand(const std::string& command, int* status) {
  const auto t0 = std::chrono::steady_clock::now();
  *status = RunKilledAfter(command, 1e9);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Files under `dir` whose name holds ".tmp-" (a temporary left behind).
inline int CountTemporaries(const std::string& dir) {
  int n = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    n += e.path().filename().string().find(".tmp-") != std::string::npos;
  return n;
}

}  // namespace bead::test
