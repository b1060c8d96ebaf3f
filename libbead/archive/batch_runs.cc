#include "libbead/archive/batch_runs.h"

#include <filesystem>
#include <map>
#include <set>

#include "libbead/core/error.h"
#include "libbead/io/csv_reader.h"

namespace bead {
namespace fs = std::filesystem;
namespace {

// Output names: stems, or paths from the common folder where stems repeat.
void NameRuns(std::vector<BatchRun>& runs, const std::string& where) {
  std::map<std::string, int> stems;
  for (const BatchRun& r : runs) ++stems[fs::path(r.run).stem().string()];
  fs::path common;
  bool first = true;
  for (const BatchRun& r : runs) {
    const fs::path dir = fs::absolute(r.run).lexically_normal().parent_path();
    if (first) {
      common = dir;
      first = false;
      continue;
    }
    fs::path shared;
    auto a = common.begin(), b = dir.begin();
    for (; a != common.end() && b != dir.end() && *a == *b; ++a, ++b) shared /= *a;
    common = shared;
  }
  std::set<std::string> seen;
  for (BatchRun& r : runs) {
    const fs::path p(r.run);
    r.name = p.stem().string();
    if (stems[r.name] > 1) {
      const fs::path rel = fs::absolute(p).lexically_normal().lexically_relative(common);
      std::string name = (rel.parent_path() / rel.stem()).string();
      for (char& c : name)
        if (c == '/') c = '_';
      r.name = name;
    }
    if (r.name.empty() || r.name[0] == '.') r.name = "run_" + r.name;
    if (!seen.insert(r.name).second)
      throw Error(Located(where, r.run, "is listed twice (two runs would write OUT/" + r.name + ")"));
  }
}

std::size_t Number(const char* text, const std::string& what) {
  char* end = nullptr;
  const long long v = std::strtoll(text, &end, 10);
  if (!text[0] || *end != '\0' || v < 0) throw Error(what + " is '" + text + "', not a whole number >= 0");
  return static_cast<std::size_t>(v);
}

}  // namespace

std::vector<BatchRun> RunsFromPaths(const std::vector<std::string>& paths, const std::string& rig) {
  std::vector<BatchRun> runs;
  for (const std::string& p : paths) runs.push_back({p, rig, ""});
  NameRuns(runs, "command line");
  return runs;
}

std::vector<BatchRun> RunsFromManifest(const std::string& manifest) {
  CsvReader csv(manifest);
  const std::vector<std::string> header = csv.Header({"run", "rig"}, "batch manifest (columns run,rig)");
  const fs::path base = fs::path(manifest).parent_path();
  std::vector<BatchRun> runs;
  while (csv.Next()) {
    if (csv.columns() < 2 || csv.Empty(0) || csv.Empty(1)) csv.Fail("a row needs a run and a rig");
    fs::path run(std::string(csv.Field(0))), rig(std::string(csv.Field(1)));
    if (run.is_relative()) run = base / run;
    if (rig.is_relative()) rig = base / rig;
    runs.push_back({run.string(), rig.string(), ""});
  }
  if (runs.empty()) throw Error(Located(manifest, "", "lists no runs"));
  NameRuns(runs, manifest);
  return runs;
}

Shard ResolveShard(const std::string& option, const std::function<const char*(const char*)>& env) {
  Shard s;
  if (!option.empty()) {
    const auto slash = option.find('/');
    if (slash == std::string::npos) throw Error("--shard '" + option + "': expected K/N (K from 1 to N)");
    const std::size_t k = Number(option.substr(0, slash).c_str(), "--shard's K");
    s.count = Number(option.substr(slash + 1).c_str(), "--shard's N");
    if (s.count == 0 || k < 1 || k > s.count)
      throw Error("--shard '" + option + "': K must be from 1 to N, and N at least 1");
    s.index = k - 1;
    s.source = "--shard " + option;
    return s;
  }
  auto pair = [&](const char* rank, const char* size, const std::string& source) {
    const char* r = env(rank);
    const char* n = env(size);
    if (!r || !n) return false;
    s.index = Number(r, rank);
    s.count = Number(n, size);
    if (s.count == 0 || s.index >= s.count)
      throw Error(std::string(rank) + "=" + r + " is not below " + size + "=" + n);
    s.source = source;
    return true;
  };
  if (const char* id = env("SLURM_ARRAY_TASK_ID"); id && env("SLURM_ARRAY_TASK_COUNT")) {
    const std::size_t count = Number(env("SLURM_ARRAY_TASK_COUNT"), "SLURM_ARRAY_TASK_COUNT");
    const std::size_t min =
        env("SLURM_ARRAY_TASK_MIN") ? Number(env("SLURM_ARRAY_TASK_MIN"), "SLURM_ARRAY_TASK_MIN") : 0;
    const std::size_t step =
        env("SLURM_ARRAY_TASK_STEP")
            ? std::max<std::size_t>(1, Number(env("SLURM_ARRAY_TASK_STEP"), "SLURM_ARRAY_TASK_STEP"))
            : 1;
    const std::size_t task = Number(id, "SLURM_ARRAY_TASK_ID");
    if (task < min || count == 0 || (task - min) / step >= count)
      throw Error("SLURM_ARRAY_TASK_ID=" + std::string(id) + " is outside the array (min " + std::to_string(min) +
                  ", step " + std::to_string(step) + ", " + std::to_string(count) + " tasks)");
    s.index = (task - min) / step;
    s.count = count;
    s.source = "Slurm array task " + std::string(id);
    return s;
  }
  if (pair("OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE", "mpirun (Open MPI)")) return s;
  if (pair("PMI_RANK", "PMI_SIZE", "mpirun (PMI)")) return s;
  s.source = "all runs";
  return s;
}

}  // namespace bead
