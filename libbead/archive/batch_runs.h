// The runs of a batch: from the command line (one rig for all) or from a
// manifest CSV with columns run,rig (runs of several rig placements;
// relative paths from the manifest's folder). Each run gets an output
// name: its file's stem, or where stems repeat (every simulated run is
// run.h5), the path from the runs' common folder with '/' as '_'
// (a/run.h5 -> a_run).
//
// A shard (K of N) takes the runs whose place in the list is K - 1 modulo N;
// it comes from --shard K/N, else a Slurm job array
// (SLURM_ARRAY_TASK_ID/_MIN/_STEP/_COUNT), else mpirun (OMPI_COMM_WORLD_RANK
// and _SIZE, or PMI_RANK and PMI_SIZE), else 1/1.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

namespace bead {

struct BatchRun {
  std::string run;   // archive path as given (resolved for a manifest)
  std::string rig;   // rig YAML path
  std::string name;  // output folder name, unique in the batch
};

std::vector<BatchRun> RunsFromPaths(const std::vector<std::string>& runs, const std::string& rig);
std::vector<BatchRun> RunsFromManifest(const std::string& manifest);

struct Shard {
  std::size_t index = 0;  // 0-based
  std::size_t count = 1;
  std::string source;  // where it came from, in words ("--shard 2/4", "Slurm array", ...)
  bool Takes(std::size_t run) const { return run % count == index; }
};

// `option`: the --shard text ("" when not given). `env` reads the
// environment (tests pass their own). Throws bead::Error naming what is wrong.
Shard ResolveShard(
    const std::string& option,
    const std::function<const char*(const char*)>& env = [](const char* k) { return std::getenv(k); });

}  // namespace bead
