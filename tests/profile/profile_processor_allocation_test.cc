// Acquisition software calls the processor at the sensor's rate: once
// constructed, it must not touch the heap. Every global operator new is
// counted here; processing a thousand varied profiles (valid, spiky,
// dropouts, no bead, no reference) must count none.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <limits>
#include <new>

#include "libbead/flow/streaming_flow.h"
#include "libbead/part/part_profile_processor.h"
#include "libbead/profile/profile_processor.h"
#include "libbead/sim/part_twin.h"
#include "tests/support/synthetic.h"

namespace {
std::atomic<long> g_allocations{0};
}

// (GCC 12 takes free() in a replaced operator delete for a pointer from a
// mismatched allocation function; here new and delete are replaced
// together, malloc and free, and match.)
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace bead {
namespace {

TEST(ProfileProcessor, AllocatesNothingPerProfile) {
  sim::SensorNoise noise;
  noise.z_sigma_mm = 0.01;
  noise.dropout_prob = 0.1;
  noise.spike_prob = 0.05;
  noise.spike_mm = 2.0;
  std::vector<test::Synthetic> profiles;
  for (unsigned i = 0; i < 1000; ++i) {
    auto p = test::Render(i % 10 == 3 ? sim::Outline{} : sim::SemicircleOutline(3.0 + (i % 5)),
                          {0.001 * (i % 17), 0.0, 30.0}, test::UniformGrid(640), noise, i);
    if (i % 10 == 7)
      for (std::size_t k = 0; k < p.x.size(); ++k)
        if (test::kRight.Contains(p.x[k])) p.z[k] = std::numeric_limits<float>::quiet_NaN();
    if (i % 2 == 1) {  // reversed x too
      std::reverse(p.x.begin(), p.x.end());
      std::reverse(p.z.begin(), p.z.end());
    }
    profiles.push_back(std::move(p));
  }
  ProfileProcessor processor(test::kLeft, test::kRight, {}, 640);
  int valid = 0, invalid = 0;
  const long before = g_allocations.load();
  for (const auto& p : profiles) {
    const BeadGeometry& g = processor.Process(p.view());
    (g.valid() ? valid : invalid) += 1;
  }
  const long allocations = g_allocations.load() - before;
  EXPECT_EQ(allocations, 0);
  EXPECT_GT(valid, 700);    // the test exercised the full path ...
  EXPECT_GE(invalid, 150);  // ... and the invalid ones
  // The counter works: a vector allocates.
  const long probe = g_allocations.load();
  std::vector<int> v(10);
  EXPECT_EQ(g_allocations.load() - probe, 1);
}

// The on-line flow too: after its first seconds (the log's first
// Savitzky-Golay window, the first compactions of a short history), an
// hour's worth of pushing and popping at 500 Hz of log and 200 Hz of
// profiles, a wheel at 20 RPM with the counter wrapping, valid and
// invalid profiles, counts no allocation.
TEST(StreamingFlow, AllocatesNothingPerCall) {
  Rig rig;
  rig.encoder.counts_per_rev = 20480;
  rig.encoder.bits = 16;
  rig.wheel_diameter_mm = 254.762;
  rig.offset_counts = 3000;
  StreamingFlow flow(rig, FlowOptions{}, 500.0, /*history_s=*/5.0);
  const double counts_per_s = 20480 * 20.0 / 60.0;
  BeadGeometry g;
  g.status = ProfileStatus::kValid;
  long pops = 0, before = 0;
  const int seconds = 900, warm = 20;
  for (int k = 0; k < seconds * 500; ++k) {
    if (k == warm * 500) before = g_allocations.load();
    const double t = k / 500.0;
    flow.PushLog(t, static_cast<int64_t>(counts_per_s * t) % 65536, 30.0);
    if (k % 5 == 0 || k % 5 == 2) {  // 200 Hz
      g.status = k % 997 == 0 ? ProfileStatus::kNoBead : ProfileStatus::kValid;
      g.area_mm2 = 10.0 + 0.01 * (k % 7);
      g.area_sigma_mm2 = 0.02 + 0.001 * (k % 3);
      flow.PushProfile(t, static_cast<int64_t>(counts_per_s * t) % 65536, g);
    }
    for (FlowSample s; flow.Pop(s);) pops += s.valid;
  }
  flow.Finish();  // the end of the run, its last windows fitted
  for (FlowSample s; flow.Pop(s);) pops += s.valid;
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_GT(pops, 0.99 * seconds * 200);  // it did produce the flow (200 profiles a second)
}

// A part's wall, its six layers through one processor three times over
// (the buffers the first rounds filled reused, as acquisition software
// keeps one processor from part to part; the second round's first profile
// still grew the list of the buffers let go): no allocation on any
// profile the third time but the first two of each layer's pass, where it
// searches wide for the pass's shift.
TEST(PartProfileProcessor, AllocatesNothingOnceItsBuffersAreFilledButOnAPassesFirstTwoProfiles) {
  sim::PartTwinConfig config;
  config.length_mm = 50.0;
  const sim::PartTwin twin = sim::SimulatePartWall(config);
  const ProfileBlock& b = twin.scan.profiles;
  const PartPlaces& places = *twin.scan.part;
  part::PartProfileProcessor processor(twin.rig, {}, b.points);
  long elsewhere = 0, valid = 0, searched = 0;
  for (int round = 0; round < 3; ++round) {
    int64_t layer = -1;
    int in_layer = 0;
    for (std::size_t k = 0; k < b.size(); ++k) {
      in_layer = places.layer[k] == layer ? in_layer + 1 : 0;
      layer = places.layer[k];
      const long before = g_allocations.load();
      const part::PartProfileGeometry& g = processor.Process(b.view(k), part::PartPlace::At(places, k));
      const long allocations = g_allocations.load() - before;
      if (round < 2) continue;
      valid += g.bead.valid() && g.no_surface.empty();
      (in_layer < 2 && layer > 0 ? searched : elsewhere) += allocations;
    }
  }
  EXPECT_EQ(elsewhere, 0);
  EXPECT_GT(searched, 0);                         // the counter sees the searches' own
  EXPECT_EQ(valid, static_cast<long>(b.size()));  // every profile measured: the whole path ran
}

}  // namespace
}  // namespace bead
