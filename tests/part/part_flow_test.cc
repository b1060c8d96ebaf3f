// The flow along a part's toolpath: each profile's place found in the
// nozzle's log (its extrusion time), Q = v_head A, and each layer's volume.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <vector>

#include "libbead/core/error.h"
#include "libbead/io/profile_stream.h"
#include "libbead/io/run_archive.h"
#include "libbead/part/part_flow.h"
#include "libbead/sim/part_twin.h"
#include "tests/support/temp_dir.h"

namespace bead {
namespace {

// The twin's wall measured and timed: each profile's geometry, flow and
// truth rows to `each`; the layers' volumes measured, and the material the
// twin laid over each layer's path (its trapezoids, in the scan's order).
struct Timed {
  part::LayerVolumes measured;
  std::map<int64_t, double> laid;
  int timed = 0, rows = 0;
};
using EachRow = std::function<void(const part::PartGeometryRow&, const part::PartFlowRow&, const sim::PartTruthRow&)>;
Timed MeasureAndTime(const sim::PartTwin& twin, const part::NozzleClock& clock, const EachRow& each) {
  ProfileStream stream("twin", twin.scan.profiles);
  Timed out;
  std::map<int64_t, std::pair<double, double>> last;  // path, material of the layer's last row
  part::MeasurePart(stream, *twin.scan.part, twin.rig, {}, [&](const part::PartGeometryRow& g) {
    const part::PartFlowRow r = part::FlowOf(g, clock, part::MeasurePartOptions{}.correct_hidden);
    const sim::PartTruthRow& t = twin.truth[g.profile];
    ++out.rows;
    out.measured.Add(r);
    if (const auto it = last.find(t.layer); it != last.end())
      out.laid[t.layer] += 0.5 * (t.area_mm2 + it->second.second) * std::abs(t.path_mm - it->second.first);
    last[t.layer] = {t.path_mm, t.area_mm2};
    if (!r.valid) return;
    ++out.timed;
    each(g, r, t);
  });
  return out;
}

// Each layer's volume against the material the twin laid over the same
// path: the areas' sampling bound (0.15 mm^2, part_wall_test.cc) over the
// length, and the corrected area's bias over a run (within 1 %,
// hidden_groove_test.cc).
void ExpectVolumes(const Timed& t, double length_mm) {
  for (const auto& [layer, volume] : t.laid)
    EXPECT_NEAR(t.measured.volumes_mm3().at(layer), volume, 0.15 * length_mm + 0.01 * volume) << "layer " << layer;
}

TEST(PartFlow, EachPlaceIsTimedWhenTheNozzleLaidItAndItsFlowIsHeadSpeedTimesArea) {
  sim::PartTwinConfig config;
  config.layers = 3;
  config.length_mm = 40.0;
  config.seed = 21;
  const sim::PartTwin twin = sim::SimulatePartWall(config);
  const part::NozzleClock clock(*twin.scan.log, "twin");
  const Timed t = MeasureAndTime(twin, clock, [&](const auto& g, const auto& r, const auto& truth) {
    // The laser line trails the nozzle by trail_mm at the head's speed:
    // the nozzle laid the place that long before the profile saw it (the
    // log's path is linear between samples: exact to rounding).
    EXPECT_NEAR(r.t_s, g.t_s - config.trail_mm / config.head_speed_mm_s, 1e-9) << g.profile;
    EXPECT_NEAR(r.head_speed_mm_s, config.head_speed_mm_s, 1e-9);
    // The area less the groove hidden under the overhangs, where there is one.
    EXPECT_DOUBLE_EQ(r.flow_mm3_s, r.head_speed_mm_s * g.area_corrected_mm2);
    // The twin's screw turned for the flow it laid there (Q = rpm D / 60),
    // read between log samples dt apart: off by at most |dQ/dt| dt, with
    // dQ/dt = v^2 dA/dpath <= v^2 wave 2 pi / period.
    const double v = config.head_speed_mm_s, dt = 1.0 / config.log_rate_hz;
    const double slope = v * v * config.area_wave_mm2 * 2.0 * M_PI / config.wave_period_mm;
    EXPECT_NEAR(r.screw_rpm * config.displacement_mm3_per_rev / 60.0, v * truth.area_mm2, slope * dt + 1e-9);
  });
  // Only a place laid before the log's first sample of its layer can be
  // without a time: at most one per layer.
  EXPECT_GE(t.timed, t.rows - config.layers);
  ExpectVolumes(t, config.length_mm);
}

// A wall laid back and forth: every other layer printed from the far end,
// its path falling in the log. Each place is timed when the nozzle laid it
// whichever way it went (the profiler trails it either way), the head's
// speed is a speed, and each layer's volume counts its steps back along
// the path. (Timed forward only, every other layer had no flow at all.)
TEST(PartFlow, AWallLaidBackAndForthIsTimedEachWay) {
  sim::PartTwinConfig config;
  config.layers = 4;
  config.length_mm = 40.0;
  config.seed = 22;
  config.alternate = true;
  const sim::PartTwin twin = sim::SimulatePartWall(config);
  const part::NozzleClock clock(*twin.scan.log, "twin");
  for (int n = 0; n < config.layers; ++n) EXPECT_EQ(clock.Direction(n), n % 2 ? -1 : 1) << n;
  const Timed t = MeasureAndTime(twin, clock, [&](const auto& g, const auto& r, const auto&) {
    EXPECT_NEAR(r.t_s, g.t_s - config.trail_mm / config.head_speed_mm_s, 1e-9) << g.profile;
    EXPECT_NEAR(r.head_speed_mm_s, config.head_speed_mm_s, 1e-9) << g.profile;
    EXPECT_GT(r.flow_mm3_s, 0.0);
  });
  EXPECT_GE(t.timed, t.rows - config.layers);
  ExpectVolumes(t, config.length_mm);
}

// The printing direction is the one the screw turned over longer; where it
// never turned, the one the head spent longer on (printing is slower than
// a travel).
TEST(PartFlow, ALayersPrintingDirectionIsWhereTheScrewTurned) {
  AcquisitionLog log;
  const auto add = [&](double t, int64_t layer, double path, double rpm) {
    log.t_s.push_back(t), log.layer.push_back(layer), log.path_mm.push_back(path), log.screw_rpm.push_back(rpm);
  };
  // Layer 0: printed back from 10 to 0 over 5 s, the screw at 60 rpm; a
  // quick travel forward with it stopped. Layer 1: the screw never turns;
  // forward over 1 s, back over 4 s.
  for (int k = 0; k <= 10; ++k) add(0.5 * k, 0, 10.0 - k, 60.0);
  for (int k = 1; k <= 10; ++k) add(5.0 + 0.1 * k, 0, k, 0.0);
  for (int k = 0; k <= 10; ++k) add(7.0 + 0.1 * k, 1, k, 0.0);
  for (int k = 1; k <= 10; ++k) add(8.0 + 0.4 * k, 1, 10.0 - k, 0.0);
  const part::NozzleClock clock(log, "log.h5");
  EXPECT_EQ(clock.Direction(0), -1);
  EXPECT_EQ(clock.Direction(1), -1);
  EXPECT_EQ(clock.Direction(2), 0);
  const auto at = clock.At(0, 7.5);
  ASSERT_TRUE(at);
  EXPECT_NEAR(at->t_s, 1.25, 1e-12);             // path 10 - t / 0.5
  EXPECT_NEAR(at->head_speed_mm_s, 2.0, 1e-12);  // 1 mm each 0.5 s, a speed whichever way
  EXPECT_NEAR(clock.At(1, 2.5)->t_s, 8.0 + 0.4 * 7.5, 1e-12);
  // A log without the screw's speed, or with a place not known: the time
  // decides, and the unknown place ends a stretch (no crash, no NaN time).
  log.screw_rpm.clear();
  log.path_mm[3] = NAN;
  const part::NozzleClock without(log, "log.h5");
  EXPECT_EQ(without.Direction(0), -1);  // back over 4 s in two pieces around the unknown place, forward over 1 s
  EXPECT_FALSE(without.At(0, 7.0)) << "timed across the unknown place (between 8 and 6 mm)";
  EXPECT_NEAR(without.At(0, 8.5)->t_s, 0.75, 1e-12);
  EXPECT_TRUE(std::isnan(without.At(1, 2.5)->screw_rpm));
  EXPECT_NEAR(without.At(1, 2.5)->t_s, 8.0 + 0.4 * 7.5, 1e-12);
}

// A log of the head's speed at 10 Hz, the head braking into a corner: 20
// mm/s, braking at a = 60 mm/s^2 from t = 0.13 s to 16 mm/s, then on. The
// path between two samples says how far the head went: where it
// accelerates evenly between samples (the interval after the braking) the
// speed at a place and its time are the motion's own; in the interval that
// holds the braking's start (a kink no sampling shows), the worst speed and
// time are off by under half what the log's samples alone give (linear
// between the logged speeds, the time linear in the path: 1.29 mm/s and
// 3.3 ms; the path's integral held, 0.52 mm/s and 0.6 ms).
TEST(PartFlow, BetweenTheLogsSamplesTheHeadMovesAsThePathBetweenThemSays) {
  constexpr double v0 = 20.0, a = 60.0, t_brake = 0.13, v_end = 16.0;
  const double t_end = t_brake + (v0 - v_end) / a;
  const auto speed = [&](double t) { return t < t_brake ? v0 : t < t_end ? v0 - a * (t - t_brake) : v_end; };
  const auto path = [&](double t) {
    const double u = std::min(std::max(t - t_brake, 0.0), t_end - t_brake);
    return v0 * std::min(t, t_brake) + v0 * u - 0.5 * a * u * u + v_end * std::max(t - t_end, 0.0);
  };
  AcquisitionLog log;
  for (int k = 0; k <= 4; ++k) {
    const double t = 0.1 * k;
    log.t_s.push_back(t), log.layer.push_back(0), log.path_mm.push_back(path(t));
    log.head_speed_mm_s.push_back(speed(t));
  }
  const part::NozzleClock clock(log, "log.h5");
  double worst_speed = 0.0, worst_time = 0.0, linear_speed = 0.0, linear_time = 0.0;
  for (double t = 0.1005; t < 0.2; t += 0.001) {  // the braking's start inside
    const auto at = clock.At(0, path(t));
    ASSERT_TRUE(at);
    worst_speed = std::max(worst_speed, std::abs(at->head_speed_mm_s - speed(t)));
    worst_time = std::max(worst_time, std::abs(at->t_s - t));
    const double w = (path(t) - path(0.1)) / (path(0.2) - path(0.1));
    linear_speed = std::max(linear_speed, std::abs((1 - w) * speed(0.1) + w * speed(0.2) - speed(t)));
    linear_time = std::max(linear_time, std::abs(0.1 + 0.1 * w - t));
  }
  std::printf("braking inside a 0.1 s interval: worst speed %.3f mm/s (linear %.3f), time %.4f s (linear %.4f)\n",
              worst_speed, linear_speed, worst_time, linear_time);
  EXPECT_LT(worst_speed, 0.5 * linear_speed);
  EXPECT_LT(worst_time, 0.5 * linear_time);
  for (double t = 0.2005; t < 0.3; t += 0.001) {  // braking ends at 0.1967: even from 0.2 on
    const auto at = clock.At(0, path(t));
    ASSERT_TRUE(at);
    EXPECT_NEAR(at->head_speed_mm_s, speed(t), 1e-9) << t;
    EXPECT_NEAR(at->t_s, t, 1e-9) << t;
  }
}

// A head speed logged in mm/min (a printer's feed rate, F) is 60 times the
// speed the path moves at: every flow would be 60 times too large. The
// clock refuses it, naming the file, the dataset and the factor; a
// commanded feed rate logged where the head brakes through a few corners
// (most of the layer at it) is the path's speed where it counts, and taken.
TEST(PartFlow, AHeadSpeedThatIsNotThePathsIsRefused) {
  sim::PartTwinConfig config;
  config.layers = 2;
  config.length_mm = 40.0;
  config.seed = 23;
  const sim::PartTwin twin = sim::SimulatePartWall(config);
  AcquisitionLog log = *twin.scan.log;
  ASSERT_EQ(log.head_speed_mm_s.size(), log.size());
  for (double& v : log.head_speed_mm_s) v *= 60.0;
  try {
    part::NozzleClock clock(log, "part.h5");
    FAIL() << "a head speed in mm/min was taken";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("part.h5"), std::string::npos) << what;
    EXPECT_NE(what.find("/log/head_speed_mm_s"), std::string::npos) << what;
    EXPECT_NE(what.find("is 60 times"), std::string::npos) << what;
  }
  // The twin's own (its path's speed), and one logged at twice the head's
  // speed at every fifth sample (two intervals in five 1.5 times the
  // path's: a feed rate the head fell short of through corners).
  EXPECT_NO_THROW(part::NozzleClock(*twin.scan.log, "part.h5"));
  log = *twin.scan.log;
  for (std::size_t i = 0; i < log.size(); ++i)
    if (i % 5 == 0) log.head_speed_mm_s[i] *= 2.0;
  EXPECT_NO_THROW(part::NozzleClock(log, "part.h5"));
}

// A layer's volume is integrated the way it went along its path, whatever
// its first step: a place scanned again just behind the last (a sensor's
// jitter at the start) takes nothing away and does not turn the layer round.
TEST(PartFlow, ALayersVolumeFollowsTheWayItWentNotItsFirstStep) {
  part::LayerVolumes v;
  const auto add = [&](int64_t layer, double path, double area) {
    part::PartFlowRow r;
    r.layer = layer, r.path_mm = path, r.area_mm2 = area, r.valid = true;
    v.Add(r);
  };
  add(0, 1.0, 10.0), add(0, 0.9, 10.0);  // a step back first
  for (int k = 1; k <= 10; ++k) add(0, 0.9 + k, 10.0);
  for (int k = 0; k <= 10; ++k) add(1, 10.0 - k, 5.0);  // laid from the far end
  EXPECT_NEAR(v.volumes_mm3().at(0), 100.0, 1e-9);
  EXPECT_NEAR(v.volumes_mm3().at(1), 50.0, 1e-9);
}

TEST(PartFlow, AWheelsLogIsNamed) {
  AcquisitionLog log;
  log.t_s = {0.0, 0.1};
  log.encoder = {0, 10};
  log.screw_rpm = {1.0, 1.0};
  try {
    part::NozzleClock clock(log, "run.h5");
    FAIL() << "a log without layer and path_mm was taken";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("run.h5"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("/log/layer"), std::string::npos);
  }
}

// How long after the nozzle laid each place the profiler saw it: on the
// twin's straight wall the laser line trails the nozzle by 30 mm at 20 mm/s,
// 1.5 s, to the log's sampling (100 Hz; the clock's error well under one
// sample). With the log's clock 2 s late, every place is seen before it
// was laid: told, not timed as a cooling.
TEST(PartFlow, ThePlacesAreSeenTheTrailsTimeAfterTheyWereLaid) {
  sim::PartTwinConfig config;
  config.layers = 2;
  config.length_mm = 30.0;
  sim::PartTwin twin = sim::SimulatePartWall(config);
  const double trail_s = config.trail_mm / config.head_speed_mm_s;
  test::TempDir dir;
  for (const double late_s : {0.0, 2.0}) {
    RunArchive scan = twin.scan;
    for (double& t : scan.log->t_s) t += late_s;
    WriteRunArchive(dir / "part.h5", scan);
    const part::PartScanFlow f =
        part::MeasurePartScanFlow(dir / "part.h5", *scan.part, &*scan.log, twin.rig, {}, 1, nullptr, nullptr);
    ASSERT_GT(f.delay.rows, 100u);
    EXPECT_NEAR(f.delay.Mean(), trail_s - late_s, 0.01) << late_s;
    EXPECT_NEAR(f.delay.min_s, trail_s - late_s, 0.01) << late_s;
    EXPECT_NEAR(f.delay.max_s, trail_s - late_s, 0.01) << late_s;
    EXPECT_EQ(f.delay.early, late_s > trail_s ? f.delay.rows : 0u) << late_s;
  }
}

}  // namespace
}  // namespace bead
