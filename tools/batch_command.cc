#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "libbead/archive/batch.h"
#include "libbead/archive/batch_shard.h"
#include "libbead/core/error.h"
#include "tools/commands.h"
#include "tools/subcommands.h"
#include "tools/occlusion_module.h"
#include "tools/occlusion_step.h"

namespace bead::tools {
namespace {

std::string Clock(double seconds) {
  if (!(seconds >= 0) || seconds > 360000) return "--:--";
  const long s = static_cast<long>(seconds + 0.5);
  char text[32];
  if (s >= 3600)
    std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  else
    std::snprintf(text, sizeof text, "%ld:%02ld", s / 60, s % 60);
  return text;
}

void PrintRunResult(std::size_t k, std::size_t of, const BatchRun& run, const RunResult& r, double seconds) {
  if (!r.ok()) {
    std::printf("[%zu/%zu] %s: %s\n", k + 1, of, run.name.c_str(), r.status.c_str());
  } else {
    char volume[64] = "no flow";
    if (!std::isnan(r.total_volume_mm3)) std::snprintf(volume, sizeof volume, "volume %.1f mm^3", r.total_volume_mm3);
    std::printf("[%zu/%zu] %s: %zu profiles, %zu valid, %zu with flow, %s, %.2f s\n", k + 1, of, run.name.c_str(),
                r.profiles, r.valid, r.flow_samples, volume, seconds);
    for (const std::string& w : r.warnings) std::printf("  warning: %s\n", w.c_str());
  }
  std::fflush(stdout);
}

}  // namespace

Run AddBatch(CLI::App& app) {
  struct Args {
    std::string rig, manifest, out, shard, occlusion = "pooled";
    std::vector<std::string> runs;
    BatchOptions options;
    unsigned threads = 0;
    bool summary_only = false, redo = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("batch", Summary("batch"));
  cmd->footer(
      "In:  RUN.h5 ... with --rig RIG.yaml, or --manifest runs.csv (columns run,rig; relative paths\n"
      "     from the manifest's folder) for runs of several rig placements.\n"
      "Out: OUT/<run>/geometry.csv and flow.csv (as bead measure and bead flow write them; no flow\n"
      "     for a run without a log; a part scan's the part forms, measured layer on layer),\n"
      "     OUT/<run>/result.csv (the run's row) and OUT/summary.csv:\n"
      "     name,run,rig,status,profiles,valid,flow_samples,total_volume_mm3,offset_counts,\n"
      "     occlusion_fraction,warnings. <run> is the file's stem, or its path from the runs'\n"
      "     common folder with '/' as '_' where stems repeat (a/run.h5 -> a_run).\n"
      "Resumable: killed at any moment and started again with the same command, it skips the runs\n"
      "     already complete (same inputs, same options) and redoes the rest; every file is written\n"
      "     atomically. A run that fails is reported in its row and the batch goes on (exit 1).\n"
      "More than one machine: each process takes every N-th run: --shard K/N, or automatically\n"
      "     from a Slurm job array (SLURM_ARRAY_TASK_ID) or mpirun (OMPI_COMM_WORLD_RANK, PMI_RANK).\n"
      "     Each shard rebuilds OUT/summary.csv from the results present when it ends;\n"
      "     --summary-only rebuilds it at any time.\n"
      "Examples:\n"
      "  bead batch --rig rig.yaml -o results runs/*.h5\n"
      "  mpirun -np 8 bead batch --rig rig.yaml -o results runs/*.h5\n"
      "  sbatch --array=0-15 --wrap 'bead batch --manifest runs.csv -o results'");
  cmd->add_option("runs", args->runs, "Run archives or part scans (.h5), or profiles CSVs")->check(CLI::ExistingFile);
  cmd->add_option("--rig", args->rig, "Rig file (YAML) of every run given on the command line")
      ->check(CLI::ExistingFile);
  cmd->add_option("--manifest", args->manifest, "CSV with columns run,rig")->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->options.out, "Output folder (created)")->required();
  cmd->add_option("--shard", args->shard, "Take the K-th of N shards of the run list (K from 1 to N)");
  cmd->add_option("--threads", args->threads, "Worker threads (0: all cores)")->capture_default_str();
  cmd->add_flag("--summary-only", args->summary_only, "Only rebuild OUT/summary.csv from the results present");
  cmd->add_flag("--redo", args->redo, "Redo runs even when their results are complete");
  auto& b = args->options.profile.bead;
  cmd->add_option("--threshold-mm", b.min_threshold_mm, "Least height that counts as bead, mm")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--spike-mm", b.spike_mm, "A point this far off its neighbours' median is a spike, mm")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  AddOcclusionOption(cmd, args->occlusion);

  return [args]() {
    std::vector<BatchRun> runs;
    if (!args->manifest.empty()) {
      if (!args->runs.empty() || !args->rig.empty())
        throw CLI::ValidationError("--manifest", "give either --manifest or --rig with runs, not both");
      runs = RunsFromManifest(args->manifest);
    } else {
      if (args->runs.empty() || args->rig.empty()) throw CLI::RequiredError("runs and --rig (or --manifest runs.csv)");
      runs = RunsFromPaths(args->runs, args->rig);
    }
    BatchOptions& options = args->options;
    options.occlusion = ParseOcclusionMode(args->occlusion);
    options.estimate = EstimateOcclusionOnDemand;
    std::error_code ec;
    std::filesystem::create_directories(options.out, ec);
    if (ec) throw Error(Located(options.out, "", "cannot create the output folder: " + ec.message()));
    if (args->summary_only) {
      const SummaryState s = WriteSummary(runs, options);
      std::printf("%s/summary.csv: %zu of %zu runs have results (%zu failed)\n", options.out.c_str(), s.complete,
                  runs.size(), s.failed);
      return 0;
    }
    Shard shard;
    try {
      shard = ResolveShard(args->shard);
    } catch (const Error& e) {
      if (args->shard.empty()) throw;
      throw CLI::ValidationError("--shard", e.what());  // a usage error: exit 2
    }
    std::printf("batch: %zu of %zu runs (shard %zu/%zu: %s) into %s\n", ShardRuns(runs, shard).size(), runs.size(),
                shard.index + 1, shard.count, shard.source.c_str(), options.out.c_str());
    std::fflush(stdout);
    const bool tty = isatty(STDERR_FILENO);
    BatchEvents events;
    events.skipped = [](std::size_t k, std::size_t of, const BatchRun& run) {
      std::printf("[%zu/%zu] %s: complete, skipped\n", k + 1, of, run.name.c_str());
    };
    if (tty)
      events.progress = [](std::size_t k, std::size_t of, const BatchRun& run, std::size_t done, std::size_t total,
                           double rate, double left_s) {
        std::fprintf(stderr, "\r[%zu/%zu] %s: %zu/%zu profiles, %.0f profiles/s, %s left   ", k + 1, of,
                     run.name.c_str(), done, total, rate, Clock(left_s).c_str());
      };
    events.finished = [tty](std::size_t k, std::size_t of, const BatchRun& run, const RunResult& r, double seconds) {
      if (tty) std::fprintf(stderr, "\r\033[K");
      PrintRunResult(k, of, run, r, seconds);
    };
    WorkerPool pool(args->threads);
    const ShardTally t = RunShard(runs, options, shard, pool, args->redo, events);
    const SummaryState& s = t.summary;
    std::printf("done: %zu runs processed, %zu skipped as complete, %zu failed; %s/summary.csv has %zu of %zu runs%s\n",
                t.processed, t.skipped, t.failed, options.out.c_str(), s.complete, runs.size(),
                s.missing.empty() ? "" : " (the rest: other shards, or not yet run)");
    return t.failed ? 1 : 0;
  };
}

}  // namespace bead::tools
