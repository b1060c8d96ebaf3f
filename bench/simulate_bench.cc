// The digital twin's speed: a 60 s run at 200 Hz with 640 points per
// profile (issue 3's case: under 10 s on one core), everything but the
// writing. Baseline, in the same run: the rig's own time, 60 s; the
// real-time factor is printed.
#include <benchmark/benchmark.h>

#include <cstdio>

#include "libbead/sim/rig_simulator.h"

namespace {

bead::sim::SimConfig Config() {
  bead::sim::SimConfig c;
  c.duration_s = 60;
  c.sensor.points = 640;
  c.extruder.command.kind = bead::sim::CommandConfig::Kind::kPrbs;
  return c;
}

double g_seconds = 0;

void BM_Simulate60s(benchmark::State& state) {
  const auto c = Config();
  for (auto _ : state) {
    const auto run = bead::sim::Simulate(c);
    benchmark::DoNotOptimize(run.truth.total_volume_mm3);
  }
  state.counters["profiles"] = 12001;
}
BENCHMARK(BM_Simulate60s)->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3)->ReportAggregatesOnly(true);

class Reporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs)
      if (r.aggregate_name == "median") g_seconds = r.GetAdjustedCPUTime();
  }
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  Reporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  if (g_seconds > 0)
    std::printf("\nBaseline: the rig's own time, 60 s. Median %.2f s CPU: %.1fx faster than real time; budget 10 s.\n",
                g_seconds, 60.0 / g_seconds);
  benchmark::Shutdown();
  return 0;
}
