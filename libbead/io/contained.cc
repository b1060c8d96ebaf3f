#include "libbead/io/contained.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <sstream>
#include <string>

#include "libbead/core/error.h"

// Sanitizers reserve terabytes of address space for their shadow memory:
// an address-space cap would stop them, not the file. Under them the
// child runs uncapped (their own allocator limits apply).
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define BEAD_NO_ADDRESS_CAP 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define BEAD_NO_ADDRESS_CAP 1
#endif
#endif

namespace bead {

bool AddressSpaceCapped() {
#ifdef BEAD_NO_ADDRESS_CAP
  return false;
#else
  return true;
#endif
}

namespace {

// The process's mapped address space, bytes (/proc/self/statm's first
// field, in pages); 0 when unknown.
std::size_t MappedBytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t pages = 0;
  if (!(statm >> pages)) return 0;
  return pages * static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
}

// The child: the probe, its outcome on the pipe as one status byte and a
// message; _exit, so that no library's exit handler runs on its state.
[[noreturn]] void RunChild(int fd, const std::function<std::string()>& work, std::size_t cap, pid_t parent,
                           double cpu_seconds) {
  // Dies with the caller; a caller already gone leaves nothing to report to.
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() != parent) _exit(1);
  const auto cpu = static_cast<rlim_t>(std::ceil(std::max(cpu_seconds, 1.0)));
  rlimit c{cpu, cpu + 1};  // SIGXCPU at the soft limit, SIGKILL at the hard
  setrlimit(RLIMIT_CPU, &c);
#ifndef BEAD_NO_ADDRESS_CAP
  if (cap > 0) {
    rlimit r{cap, cap};
    setrlimit(RLIMIT_AS, &r);
  }
#else
  (void)cap;
#endif
  char status = 'o';
  std::string message;
  try {
    message = work();
  } catch (const Error& e) {
    status = 'e', message = e.what();
  } catch (const std::bad_alloc&) {
    status = 'm';
  } catch (const std::exception& e) {
    status = 'x', message = e.what();
  } catch (...) {
    status = 'x';
  }
  std::string out = status + message;
  const char* p = out.data();
  std::size_t left = out.size();
  while (left > 0) {
    const ssize_t w = write(fd, p, left);
    if (w <= 0) break;
    p += w, left -= static_cast<std::size_t>(w);
  }
  _exit(0);
}

// A child's state letter and CPU time in clock ticks (/proc/PID/stat's
// third, fourteenth and fifteenth fields); false when it cannot be read.
bool ChildCpu(pid_t pid, char& state, unsigned long long& ticks) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(in, line)) return false;
  const std::size_t close = line.rfind(')');  // the name may hold spaces
  if (close == std::string::npos || close + 2 >= line.size()) return false;
  std::istringstream rest(line.substr(close + 2));
  std::string skip;
  unsigned long long user = 0, system = 0;
  rest >> state;
  for (int field = 4; field <= 13; ++field) rest >> skip;
  if (!(rest >> user >> system)) return false;
  ticks = user + system;
  return true;
}

enum class Outcome { kFinished, kTimedOut, kBlocked };

// A child asleep without a tick of CPU time for this long is blocked, not
// working: a lock another thread of the caller held when it forked (a
// sanitizer's allocator, whose locks fork does not take; libhdf5's global
// lock) stays held in the child forever. Reading headers never sleeps
// this long.
constexpr double kBlockedSeconds = 2.0;

// A child still working when its wall time is up - runnable (state R) or
// its CPU time still rising - is slow, not stuck: a loaded machine starves
// it (seen: a probe run under nice beside a build on two cores got a tick
// of CPU every two seconds, and a valid file was called corrupt). It is
// given up to kStarvedTimes its wall time while it works; its CPU limit
// still bounds the work a damaged file can make it do. "Rising": a tick
// within kRisingSeconds.
constexpr double kStarvedTimes = 6.0;
constexpr double kRisingSeconds = 1.0;

// Reads the child's report until it closes the pipe or the time is up;
// `watch`: also until the child is found blocked (above). `given`: the
// wall time it was given when it timed out, seconds.
Outcome ReadReport(int fd, double seconds, pid_t child, bool watch, std::string& report, double& given) {
  const auto start = std::chrono::steady_clock::now();
  const auto deadline = start + std::chrono::duration<double>(seconds);
  const auto ceiling = start + std::chrono::duration<double>(kStarvedTimes * seconds);
  // Not rising until a tick is seen.
  auto last_progress = start;
  auto last_tick = start - std::chrono::seconds(2);  // kRisingSeconds ago and more
  unsigned long long last_ticks = 0;
  char buf[4096];
  for (;;) {
    const auto now = std::chrono::steady_clock::now();
    char state = '?';
    unsigned long long ticks = 0;
    if (ChildCpu(child, state, ticks)) {
      if (ticks != last_ticks) last_tick = now;
      if (state != 'S' || ticks != last_ticks) last_progress = now, last_ticks = ticks;
      if (watch && std::chrono::duration<double>(now - last_progress).count() >= kBlockedSeconds)
        return Outcome::kBlocked;
    }
    const bool working = state == 'R' || std::chrono::duration<double>(now - last_tick).count() < kRisingSeconds;
    auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now);
    if (left.count() <= 0 && working) left = std::chrono::duration_cast<std::chrono::milliseconds>(ceiling - now);
    if (left.count() <= 0) {
      given = std::max(seconds, std::chrono::duration<double>(now - start).count());
      return Outcome::kTimedOut;
    }
    pollfd p{fd, POLLIN, 0};
    const int ready = poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 250)));
    if (ready < 0 && errno == EINTR) continue;
    if (ready < 0) return Outcome::kTimedOut;
    if (ready == 0) continue;
    const ssize_t n = read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return Outcome::kFinished;
    report.append(buf, static_cast<std::size_t>(n));
  }
}

// One child: forked, its report read, reaped (killed first unless it
// finished). Returns false where fork or pipe is unavailable.
struct Attempt {
  Outcome outcome = Outcome::kFinished;
  int status = 0;
  double given = 0.0;  // wall time, seconds
  std::string report;
};
bool RunChildOnce(const std::function<std::string()>& work, const ContainLimits& limits, bool watch, Attempt& out) {
  int fds[2];
  // Close-on-exec: a child another thread starts meanwhile does not hold
  // the pipe open past this one's end.
  if (pipe2(fds, O_CLOEXEC) != 0) return false;
  const std::size_t mapped = MappedBytes();
  const std::size_t cap = mapped > 0 ? mapped + limits.memory_bytes : 0;
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]), close(fds[1]);
    return false;
  }
  if (pid == 0) {
    close(fds[0]);
    RunChild(fds[1], work, cap, parent, limits.cpu_seconds);
  }
  close(fds[1]);
  out.outcome = ReadReport(fds[0], limits.seconds, pid, watch, out.report, out.given);
  close(fds[0]);
  if (out.outcome != Outcome::kFinished) kill(pid, SIGKILL);
  while (waitpid(pid, &out.status, 0) < 0 && errno == EINTR) {
  }
  return true;
}

}  // namespace

ContainLimits LimitsForWholeFile(const std::string& path) {
  ContainLimits limits;
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  const double extra = ec ? 0.0 : static_cast<double>(bytes) / 32e6;
  limits.seconds += extra;
  limits.cpu_seconds += extra;
  return limits;
}

void ProbeContained(const std::string& path, const std::string& library, const std::function<void()>& probe,
                    const ContainLimits& limits) {
  RunContained(
      path, library,
      [&] {
        probe();
        return std::string();
      },
      limits);
}

std::string RunContained(const std::string& path, const std::string& library, const std::function<std::string()>& work,
                         const ContainLimits& limits) {
  // A child found blocked (ReadReport) is not the file's doing: forked
  // again once, that one given the whole time.
  Attempt a;
  for (int attempt = 0; attempt < 2; ++attempt) {
    a = Attempt{};
    if (!RunChildOnce(work, limits, attempt == 0, a)) return work();
    if (a.outcome != Outcome::kBlocked) break;
  }
  const bool finished = a.outcome == Outcome::kFinished;
  const int status = a.status;
  const std::string& report = a.report;
  const std::string corrupt = "corrupt (the " + library + " library failed reading it: ";
  if (!finished) {
    char what[80];
    std::snprintf(what, sizeof what, "it did not finish in %.0f s)", a.given);
    throw Error(Located(path, "", corrupt + what));
  }
  if (WIFSIGNALED(status) && WTERMSIG(status) == SIGXCPU) {
    char what[80];
    std::snprintf(what, sizeof what, "it used more than %.0f s of CPU time)", limits.cpu_seconds);
    throw Error(Located(path, "", corrupt + what));
  }
  if (WIFSIGNALED(status) || report.empty())
    throw Error(Located(path, "",
                        corrupt +
                            (WIFSIGNALED(status) ? std::string(strsignal(WTERMSIG(status)))
                                                 : std::string("it stopped without a word")) +
                            ")"));
  switch (report[0]) {
    case 'o':
      return report.substr(1);
    case 'e':
      throw Error(report.substr(1));
    case 'm':
      throw Error(
          Located(path, "",
                  corrupt + "it asked for more than " + std::to_string(limits.memory_bytes >> 20) + " MB of memory)"));
    default:
      throw Error(Located(path, "", corrupt + (report.size() > 1 ? report.substr(1) : "an unknown failure") + ")"));
  }
}

}  // namespace bead
