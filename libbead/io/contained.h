// Reading an untrusted file where a fault inside a dependency cannot take
// the caller down. libhdf5 and libmatio trust a file's metadata: a
// damaged attribute can overflow a buffer inside H5Aexists_by_name, a
// damaged .mat header can make libmatio allocate gigabytes before it says
// anything. Validation of our own (h5::File's type and size checks) stops
// what it can see; the rest is read first in a child process (fork), its
// address space capped a fixed budget above what the caller already maps,
// its wall and CPU time bounded (seconds: reading headers and a small
// file's data needs well under one; a probe that takes longer is kept busy
// by a damaged file), and killed with its caller (a caller that dies or is
// killed never leaves a probe spinning). A child found asleep without using
// the CPU for two seconds is blocked, not busy: fork copies the caller's
// locks but not the threads holding them (a sanitizer's allocator,
// libhdf5's global lock, held by another of the caller's threads at that
// instant), and such a child waits forever. That is no fault of the file:
// the child is forked once more and given the whole time. A child still
// working when its wall time is up (runnable, or its CPU time rising) is
// starved by a loaded machine, not stuck: it is given up to six times the
// wall time while it works (its CPU limit bounds the work). Only when that probe finishes does the caller read
// the file itself; a probe that crashes, runs out of its budget or time is
// the file's fault, said with the file's name, and the caller never
// touches it.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

namespace bead {

struct ContainLimits {
  std::size_t memory_bytes = std::size_t{1} << 30;  // beyond what the process maps when the probe starts
  double seconds = 10.0;                            // wall time
  double cpu_seconds = 8.0;                         // the child's CPU time (RLIMIT_CPU)
};

// Limits for work that reads the whole file at `path`: the defaults plus
// one second (wall and CPU) for every 32 MB of it.
ContainLimits LimitsForWholeFile(const std::string& path);

// Whether the child's address space is capped (ContainLimits::bytes): not
// under a sanitizer (gcc's or clang's), which reserves terabytes of
// address space for its shadow memory; there only the time bounds apply.
bool AddressSpaceCapped();

// Runs `work` in a child process under `limits` and returns what it
// returned (bytes: the child's result, serialised). Throws bead::Error
// with work's own message when it threw one (a file our validation
// refused); throws bead::Error "PATH: corrupt (the LIBRARY library failed
// reading it: ...)" when it crashed or exhausted its memory or time. Where
// fork is unavailable the work runs in place.
std::string RunContained(const std::string& path, const std::string& library, const std::function<std::string()>& work,
                         const ContainLimits& limits = {});

// The same for a probe whose result is only that it finished: the caller
// then reads the file itself.
void ProbeContained(const std::string& path, const std::string& library, const std::function<void()>& probe,
                    const ContainLimits& limits = {});

}  // namespace bead
