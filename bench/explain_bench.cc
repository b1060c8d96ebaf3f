// explain's cost against the flow's, on a 10-minute run at 200 Hz with 640
// points per profile (issue 29: `bead explain` within 10 times `bead
// flow`), as the two commands do it: the run archive read and every
// profile measured (occlusion pooled, as both default to) and Q = v A
// computed; the explain then identifies the base model at the rate it
// explains (a long run's profiles averaged in bins, run_series.h) and runs
// the loop with its offset profile. The twin's run is written to a
// temporary archive once. Wall time: the profiles are measured on every
// core, the loop on one. The ratio is printed.
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "libbead/archive/measured_run.h"
#include "libbead/archive/open_run.h"
#include "libbead/explain/run_explain.h"
#include "libbead/explain/run_series.h"
#include "libbead/flow/flow.h"
#include "libbead/model/identify.h"
#include "libbead/occlusion/occlusion_fit.h"
#include "libbead/sim/rig_simulator.h"
#include "libbead/sim/sim_writer.h"

namespace {

// The twin's 10-minute run as an archive (written once, removed at exit).
struct Archive {
  std::string dir;
  bead::Rig rig;
  Archive() {
    bead::sim::SimConfig c;
    c.seed = 31;
    c.duration_s = 600;
    c.sensor.points = 640;
    c.extruder.command.kind = bead::sim::CommandConfig::Kind::kPrbs;
    const bead::sim::SimulatedRun run = bead::sim::Simulate(c);
    dir = (std::filesystem::temp_directory_path() / ("bead-explain-bench-" + std::to_string(getpid()))).string();
    bead::sim::WriteSimulatedRun(dir, run);
    rig = run.rig_file;
  }
  ~Archive() { std::filesystem::remove_all(dir); }
};
const Archive& TenMinuteRun() {
  static const Archive archive;
  return archive;
}

struct Measured {
  bead::MeasuredRun run;
  bead::FlowResult flow;
};

Measured Flow(const Archive& a, bead::WorkerPool& pool) {
  bead::MeasureRunOptions o;
  o.estimate = bead::occlusion::EstimateOcclusion;
  Measured m;
  m.run = bead::MeasureWholeRun(bead::OpenRun(a.dir + "/run.h5", pool), a.rig, pool, o);
  m.flow =
      bead::ComputeFlow(a.rig, m.run.run.profiles, m.run.geometry, *m.run.run.log, {}, m.run.corrected, m.run.sigma);
  return m;
}

double g_flow_s = 0, g_explain_s = 0;

void BM_Flow10MinRun(benchmark::State& state) {
  const auto& r = TenMinuteRun();
  bead::WorkerPool pool;
  for (auto _ : state) {
    const Measured m = Flow(r, pool);
    benchmark::DoNotOptimize(m.flow.total_volume_mm3);
  }
}

void BM_Explain10MinRun(benchmark::State& state) {
  const auto& r = TenMinuteRun();
  bead::WorkerPool pool;
  std::size_t samples = 0;
  for (auto _ : state) {
    const Measured m = Flow(r, pool);
    std::vector<double> t, u, y;
    for (const auto& s : m.flow.samples)
      if (s.valid) t.push_back(s.t_s), u.push_back(s.screw_rpm), y.push_back(s.flow_mm3_s);
    const std::size_t bin = bead::explain::ExplainBinOf(m.flow);
    bead::model::IdentifyOptions o;
    o.poles = o.zeros = 2;
    const auto base = bead::model::IdentifyTransferFunction(bead::explain::AverageInBins(t, bin),
                                                            bead::explain::AverageInBins(u, bin),
                                                            bead::explain::AverageInBins(y, bin), o);
    const bead::explain::MeasuredFlow view{"bench", &m.run.run.profiles, &m.run.geometry, &*m.run.run.log,
                                           &m.flow, &m.run.corrected,    &m.run.sigma};
    const auto e = bead::explain::ExplainMeasuredRun(r.rig, view, nullptr, base.tf, base.offset, {});
    samples = e.series.data.size();
    benchmark::DoNotOptimize(e.report.after.rms);
  }
  state.counters["samples_explained"] = static_cast<double>(samples);
}

BENCHMARK(BM_Flow10MinRun)->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3)->UseRealTime();
BENCHMARK(BM_Explain10MinRun)->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3)->UseRealTime();

class Reporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      if (r.aggregate_name != "median") continue;
      (r.run_name.function_name == "BM_Flow10MinRun" ? g_flow_s : g_explain_s) = r.GetAdjustedRealTime();
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  Reporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  if (g_flow_s > 0 && g_explain_s > 0)
    std::printf(
        "\nBaseline: the flow of the same run, median %.2f s. Explain median %.2f s: %.1fx the flow's; "
        "budget 10x.\n",
        g_flow_s, g_explain_s, g_explain_s / g_flow_s);
  benchmark::Shutdown();
  return 0;
}
