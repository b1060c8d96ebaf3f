// A part profile measured against the layer below (part/measure_part.h:
// the surface below interpolated along the path, the lateral registration,
// the added bead) against the wheel's per-profile geometry on the same
// profiles (a bead on the reference line): the bar is a part
// profile at no less than half the wheel's rate for the same number of
// points. The profiles are the twin's straight wall (sim/part_twin.h):
// 800 points over 40 mm, 10 um noise, three layers of 100 profiles (and,
// for the rate once each layer's groove shape is pooled, of 800).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>

#include "libbead/io/profile_stream.h"
#include "libbead/part/measure_part.h"
#include "libbead/part/part_profile_processor.h"
#include "libbead/profile/profile_processor.h"
#include "libbead/sim/part_twin.h"

namespace {

// The wall of `length_mm` (50: 100 profiles a layer, half of them
// those a layer's groove shape is pooled on; 400: 800 a layer).
// frame_moving: the profiler's frame moves sideways along the path by a
// known amount (PartTwinConfig::frame_x_wave_mm 0.37 mm), each profile's
// points then on another grid in the bed frame.
const bead::sim::PartTwin& Wall(int length_mm = 50, bool frame_moving = false) {
  static std::map<std::pair<int, bool>, bead::sim::PartTwin> twins;
  auto it = twins.find({length_mm, frame_moving});
  if (it == twins.end()) {
    bead::sim::PartTwinConfig c;
    c.layers = 3;
    c.length_mm = length_mm;
    c.frame_x_wave_mm = frame_moving ? 0.37 : 0.0;
    it = twins.emplace(std::pair{length_mm, frame_moving}, bead::sim::SimulatePartWall(c)).first;
  }
  return it->second;
}

void Rate(benchmark::State& state, const bead::sim::PartTwin& twin) {
  const auto profiles = static_cast<double>(state.iterations() * twin.scan.profiles.size());
  state.SetItemsProcessed(static_cast<int64_t>(profiles));
  state.counters["profiles_per_s"] = benchmark::Counter(profiles, benchmark::Counter::kIsRate);
  state.counters["points"] = static_cast<double>(twin.scan.profiles.points);
}
// Every profile of the wall, each layer against the one below; with the
// groove hidden under the overhangs estimated (range 0 = 1: the default)
// or not (0: the area seen only); range 1: the wall's length, mm; range 2
// (1): the profiler's frame moving sideways; range 3 (0): no lateral
// registration either, the naive layer subtraction (the surface below
// interpolated along the path, the gains, the bead's area: the floor of
// what a part profile costs here).
void BM_PartProfile(benchmark::State& state) {
  const int length_mm = static_cast<int>(state.range(1));
  const bead::sim::PartTwin& twin = Wall(length_mm, state.range(2) != 0);
  bead::part::MeasurePartOptions options;
  options.correct_hidden = state.range(0) != 0;
  options.register_layers = state.range(3) != 0;
  std::size_t valid = 0;
  for (auto _ : state) {
    state.PauseTiming();
    bead::ProfileStream stream("wall", twin.scan.profiles);
    state.ResumeTiming();
    bead::part::MeasurePart(stream, *twin.scan.part, twin.rig, options,
                            [&](const bead::part::PartGeometryRow& r) { valid += r.bead.valid(); });
  }
  benchmark::DoNotOptimize(valid);
  Rate(state, twin);
}

// Every profile of the wall as it arrives (part/part_profile_processor.h:
// the wheel's kernel over the layer below, registered by Gauss-Newton steps
// from the pass's last shift; each profile kept for the next layer; the
// pass's first two profiles searched wide): the area seen, as the wheel's
// per-profile area is before its occlusion correction. Range 0: the wall's
// length, mm (50: 100 profiles a layer; 400: 800).
void BM_PartProfileAsItArrives(benchmark::State& state) {
  const bead::sim::PartTwin& twin = Wall(static_cast<int>(state.range(0)), state.range(1) != 0);
  const bead::ProfileBlock& b = twin.scan.profiles;
  const bead::PartPlaces& places = *twin.scan.part;
  std::size_t valid = 0;
  // One processor over the wall again and again, as acquisition software
  // keeps one (and the wheel's bench its ProfileProcessor): its buffers
  // reused after the first layers, layer 0 of each pass on the bed again.
  bead::part::PartProfileProcessor processor(twin.rig, {}, b.points);
  for (auto _ : state) {
    for (std::size_t k = 0; k < b.size(); ++k) {
      const auto place = bead::part::PartPlace::At(places, k);
      valid += processor.Process(b.view(k), place).bead.status == bead::ProfileStatus::kValid;
    }
  }
  benchmark::DoNotOptimize(valid);
  Rate(state, twin);
}

// The baseline: the wheel's geometry (a bead on the reference line) on the
// same profiles. Range 0: the wall's length, mm, as the part's benches (50:
// 300 profiles, 1.9 MB of points; 400: 2400 profiles, 15 MB, read from
// memory as the part's are).
void BM_WheelProfileOnThePart(benchmark::State& state) {
  const bead::sim::PartTwin& twin = Wall(static_cast<int>(state.range(0)));
  const bead::ProfileBlock& b = twin.scan.profiles;
  bead::ProfileProcessor processor(twin.rig.reference_left, twin.rig.reference_right, {}, b.points);
  double sum = 0.0;
  for (auto _ : state)
    for (std::size_t k = 0; k < b.size(); ++k) sum += processor.Process(b.view(k)).area_mm2;
  benchmark::DoNotOptimize(sum);
  Rate(state, twin);
}

BENCHMARK(BM_PartProfile)
    ->Args({1, 50, 0, 1})
    ->Args({0, 50, 0, 1})
    ->Args({1, 400, 0, 1})
    ->Args({0, 50, 1, 1})
    ->Args({0, 50, 0, 0})
    ->Repetitions(5)
    ->MinTime(0.5)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PartProfileAsItArrives)
    ->Args({50, 0})
    ->Args({400, 0})
    ->Args({50, 1})
    ->Repetitions(5)
    ->MinTime(0.5)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WheelProfileOnThePart)->Arg(50)->Arg(400)->Repetitions(5)->MinTime(0.5)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
