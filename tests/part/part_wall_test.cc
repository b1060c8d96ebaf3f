// A wall printed by the twin, layer by layer: each layer's bead measured
// against the layer below (registered laterally) recovers what the layer
// added where the sensor can see it, its height and width, and the wall's
// wander; beside it, the naive subtraction of the layer below as recorded.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "libbead/io/profile_stream.h"
#include "libbead/io/run_archive.h"
#include "libbead/part/measure_part.h"
#include "libbead/sim/part_twin.h"
#include "tests/support/scaled_twin.h"
#include "tests/support/temp_dir.h"
#include "tests/support/error_stats.h"

namespace bead {
namespace {

std::vector<part::PartGeometryRow> Measure(const RunArchive& scan, const Rig& rig, bool register_layers) {
  ProfileStream stream("twin", scan.profiles);
  part::MeasurePartOptions options;
  options.register_layers = register_layers;
  options.correct_hidden = false;  // the area seen is what these tests are about (hidden_groove_test.cc: the rest)
  std::vector<part::PartGeometryRow> rows;
  part::MeasurePart(stream, *scan.part, rig, options, [&](const part::PartGeometryRow& r) { rows.push_back(r); });
  return rows;
}

struct Errors {
  std::vector<double> area, height, width, offset;
  int valid = 0, shift_found = 0, shift_covered = 0;
};

double Mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? NAN : s / v.size();
}
using test::Rms;

void Collect(const sim::PartTwin& twin, const std::vector<part::PartGeometryRow>& rows, Errors& e) {
  std::vector<double> pass_shift(64, 0.0);
  for (const auto& t : twin.truth) pass_shift[t.layer] = t.pass_shift_mm;
  for (const auto& r : rows) {
    const sim::PartTruthRow& t = twin.truth[r.profile];
    if (!r.bead.valid()) continue;
    ++e.valid;
    e.area.push_back(r.bead.area_mm2 - t.visible_area_mm2);
    e.height.push_back(r.bead.height_mm - t.height_mm);
    e.width.push_back(r.bead.width_mm - t.width_mm);
    if (r.layer == 0 || !std::isfinite(r.offset_below_mm)) continue;
    e.offset.push_back(r.offset_below_mm - t.offset_below_mm);
    // The layer below moved into this pass's frame: its head's error less this one's.
    const double truth = pass_shift[r.layer - 1] - pass_shift[r.layer];
    ++e.shift_found;
    e.shift_covered += std::abs(r.bead.shift_mm - truth) <= 2.0 * r.bead.shift_sigma_mm;
  }
}

// Tolerances from the twin's sampling and noise (PartTwinConfig defaults):
// points 0.05 mm apart with 0.01 mm of noise, walls up to h = 1.5 mm
// high where a bead overhangs the one below. Each of the four walls (two
// of the new surface, two of the old) is known to within one spacing, so
// a profile's area is off by at most 4 * h * 0.05 / 2 = 0.15 mm^2; height
// is a median of three gains, each with the noise of two points
// (sqrt 2 * 0.01); a width's two edges each within a spacing: 0.1 mm.
constexpr double kAreaBound = 0.15, kWidthBound = 0.1, kHeightNoise = 0.0141;

TEST(PartWall, EachLayerIsMeasuredAgainstTheOneBelowWhereTheNaiveSubtractionIsNot) {
  Errors registered, naive;
  for (uint64_t seed : {1u, 2u, 3u, 4u}) {
    sim::PartTwinConfig config;
    config.seed = seed;
    const sim::PartTwin twin = sim::SimulatePartWall(config);
    Collect(twin, Measure(twin.scan, twin.rig, true), registered);
    Collect(twin, Measure(twin.scan, twin.rig, false), naive);
  }
  const std::size_t n = registered.area.size();
  std::printf(
      "registered: area %+.4f rms %.4f mm^2, width rms %.4f, height rms %.4f mm, offset rms %.4f mm in %d of %d, "
      "shift within 2 sigma %d; naive: area %+.4f rms %.4f, offset rms %.4f\n",
      Mean(registered.area), Rms(registered.area), Rms(registered.width), Rms(registered.height),
      Rms(registered.offset), registered.shift_found, 4 * 1000, registered.shift_covered, Mean(naive.area),
      Rms(naive.area), Rms(naive.offset));
  ASSERT_EQ(registered.valid, static_cast<int>(n));
  EXPECT_EQ(n, 4u * 1200u) << "every profile of the wall is measured";
  // Unbiased within four standard errors, and each profile within its bound.
  EXPECT_LT(std::abs(Mean(registered.area)), 4.0 * kAreaBound / std::sqrt(static_cast<double>(n)) + 0.02);
  EXPECT_LT(Rms(registered.area), kAreaBound);
  EXPECT_LT(Rms(registered.width), kWidthBound);
  EXPECT_LT(Rms(registered.height), 2.0 * kHeightNoise);
  // The naive subtraction keeps the passes' lateral error (0.2 mm sigma
  // each): several times the area error and the wander's.
  EXPECT_GT(Rms(naive.area), 5.0 * Rms(registered.area));
  EXPECT_GT(Rms(naive.offset), 5.0 * Rms(registered.offset));
  // The wall's wander, where the layer below shows beside the new bead:
  // found in most profiles, to the sampling of a wall (0.05 / sqrt 12 mm
  // for each of the two passes' walls).
  EXPECT_GT(registered.shift_found, static_cast<int>(0.8 * 4 * 1000));
  EXPECT_LT(Rms(registered.offset), 2.0 * 0.05 / std::sqrt(12.0) * std::sqrt(2.0) + 0.01);
  // The shift's interval: within two sigmas in 90 % or more of the rows.
  EXPECT_GE(registered.shift_covered, static_cast<int>(0.9 * registered.shift_found));
}

// A profiler whose frame moves sideways along the path by a known amount:
// each profile's points lie on another grid in the bed frame, so the layer
// below is blended point by point from two grids and the registration
// sums point by point (part/surface_below.h, part/registration.cc), not on
// one grid eight at a time. The same bounds hold.
TEST(PartWall, AProfilerFrameMovingSidewaysOffTheGridMeasuresAsWell) {
  Errors e;
  for (uint64_t seed : {1u, 2u}) {
    sim::PartTwinConfig config;
    config.seed = seed;
    config.frame_x_wave_mm = 0.37;
    const sim::PartTwin twin = sim::SimulatePartWall(config);
    Collect(twin, Measure(twin.scan, twin.rig, true), e);
  }
  const std::size_t n = e.area.size();
  std::printf("frame moving: area %+.4f rms %.4f mm^2, width rms %.4f, height rms %.4f, offset rms %.4f mm in %d\n",
              Mean(e.area), Rms(e.area), Rms(e.width), Rms(e.height), Rms(e.offset), e.shift_found);
  EXPECT_EQ(n, 2u * 1200u) << "every profile of the wall is measured";
  EXPECT_LT(std::abs(Mean(e.area)), 4.0 * kAreaBound / std::sqrt(static_cast<double>(n)) + 0.02);
  EXPECT_LT(Rms(e.area), kAreaBound);
  EXPECT_LT(Rms(e.width), kWidthBound);
  EXPECT_LT(Rms(e.height), 2.0 * kHeightNoise);
  EXPECT_GT(e.shift_found, static_cast<int>(0.8 * 2 * 1000));
  EXPECT_LT(Rms(e.offset), 2.0 * 0.05 / std::sqrt(12.0) * std::sqrt(2.0) + 0.01);
  EXPECT_GE(e.shift_covered, static_cast<int>(0.9 * e.shift_found));
}

// A head that misses its line by millimetres from pass to pass (2 mm
// sigma; at this seed layer 1 lies 5.6 mm off layer 0 in the profiler's
// frame and layer 2 3.7 mm off layer 1, both beyond the registration's
// first range of +-3 mm). Each is found where it is (part/registration.cc:
// a pass's first searches look over the whole span; a least at a range's
// end widens it), not at a false least inside the range (layer 1's at
// -0.08 mm, its sigma 0.02, constrained: the areas 0.7 mm^2 off), and the
// walls' bounds hold.
TEST(PartWall, APassShiftedBeyondTheFirstSearchRangeIsFoundWhereItIs) {
  sim::PartTwinConfig config;
  config.seed = 3;
  config.layers = 3;
  config.length_mm = 30.0;
  config.pass_shift_sigma_mm = 2.0;
  const sim::PartTwin twin = sim::SimulatePartWall(config);
  Errors e;
  Collect(twin, Measure(twin.scan, twin.rig, true), e);
  const std::size_t n = e.area.size();
  std::printf("far shift: area %+.4f rms %.4f mm^2, offset rms %.4f mm in %d, shift within 2 sigma %d\n", Mean(e.area),
              Rms(e.area), Rms(e.offset), e.shift_found, e.shift_covered);
  EXPECT_EQ(n, twin.truth.size()) << "every profile of the wall is measured";
  EXPECT_LT(Rms(e.area), kAreaBound);
  EXPECT_LT(Rms(e.width), kWidthBound);
  EXPECT_GT(e.shift_found, static_cast<int>(0.8 * 2 * 60));  // of layers 1 and 2's 60 profiles each
  EXPECT_GE(e.shift_covered, static_cast<int>(0.9 * e.shift_found));
}

// The default wall of three layers at a scale (tests/support/scaled_twin.h).
sim::PartTwin ScaledWall(double k) {
  sim::PartTwinConfig c;
  c.seed = 1;
  c.layers = 3;
  return sim::SimulatePartWall(test::Scaled(c, k));
}

// The default wall four times larger (a large-scale printer's 24 mm bead
// seen by a profiler whose points lie 0.2 mm apart, its noise 0.04 mm) and
// a tenth its size (a glue bead 0.6 mm wide over a field of +-2 mm, points
// 5 um apart) is measured as the wall itself: its shifts found in as many
// profiles (where a layer lies straight over the one below, nothing of
// that one shows and no shift is found, at any scale), its areas, widths
// and offsets off by k^2, k and k times the wall's. Four times larger, a
// wall's sampling placed a shift no closer than spacing / sqrt 12 =
// 0.058 mm, beyond the 0.05 mm a shift's sigma was held to: no shift was
// found on any layer ("the layer below shows nowhere beside the new
// bead"), no wander reported. A tenth the size, the shift was searched
// over +-3 mm, wider than the field: every cost 0, no shift found.
TEST(PartWall, AWallFourTimesLargerOrATenthTheSizeIsMeasuredAsTheWall) {
  Errors e1;
  const sim::PartTwin wall = ScaledWall(1.0);
  Collect(wall, Measure(wall.scan, wall.rig, true), e1);
  for (double k : {4.0, 0.1}) {
    Errors ek;
    const sim::PartTwin scaled = ScaledWall(k);
    Collect(scaled, Measure(scaled.scan, scaled.rig, true), ek);
    std::printf("wall / %g times the size: area rms %.4f / %.6f mm^2, offset rms %.4f / %.5f mm in %d / %d\n", k,
                Rms(e1.area), Rms(ek.area), Rms(e1.offset), Rms(ek.offset), e1.shift_found, ek.shift_found);
    EXPECT_EQ(ek.area.size(), scaled.truth.size()) << k << ": every profile of the wall is measured";
    EXPECT_LT(Rms(ek.area), k * k * kAreaBound) << k;
    EXPECT_LT(Rms(ek.width), k * kWidthBound) << k;
    // As many shifts found, within a tenth (the search's own steps are
    // not all in spacings), and each to its sampling.
    EXPECT_GE(ek.shift_found, static_cast<int>(0.9 * e1.shift_found)) << k;
    EXPECT_LT(Rms(ek.offset), k * (2.0 * 0.05 / std::sqrt(12.0) * std::sqrt(2.0) + 0.01)) << k;
    EXPECT_GE(ek.shift_covered, static_cast<int>(0.9 * ek.shift_found)) << k;
  }
}

// A fine sensor (1 um of noise, read at the 2 um floor) over a textured
// bed: a ripple of 35 um (25 um RMS) at 1.7 mm on the bare bed, rougher
// than 10 noises, smoother than a bead's threshold (0.05 mm). The bed line
// through the reference areas is still the bed: every profile of the first
// layer is measured (each was refused as no line before the threshold
// bounded the test), its area within the walls' sampling bound, the
// ripple's own share of the trapezoid beside each foot (under 35 um over
// a spacing on each side) well inside it.
TEST(PartWall, AFineSensorOverATexturedBedMeasuresTheFirstLayer) {
  sim::PartTwinConfig config;
  config.seed = 3;
  config.layers = 1;
  config.noise_mm = 0.001;
  sim::PartTwin twin = sim::SimulatePartWall(config);
  ProfileBlock& b = twin.scan.profiles;
  const PartPlaces& places = *twin.scan.part;
  for (std::size_t i = 0; i < b.size(); ++i)
    for (std::size_t j = 0; j < b.points; ++j) {
      float& z = b.z_mm[i * b.points + j];
      const double x_bed = b.view(i).x_mm[j] + places.frame_x_mm[i];
      if (z + places.frame_z_mm[i] < 0.005) z += static_cast<float>(0.035 * std::sin(2.0 * M_PI * x_bed / 1.7));
    }
  Errors e;
  Collect(twin, Measure(twin.scan, twin.rig, true), e);
  std::printf("textured bed: %d of %zu valid, area %+.4f rms %.4f mm^2\n", e.valid, b.size(), Mean(e.area),
              Rms(e.area));
  EXPECT_EQ(e.valid, static_cast<int>(b.size()));
  EXPECT_LT(Rms(e.area), kAreaBound);
}

TEST(PartWall, AStreamedArchiveMeasuresAsTheScanInMemory) {
  test::TempDir dir;
  sim::PartTwinConfig config;
  config.layers = 3;
  config.length_mm = 30.0;
  const sim::PartTwin twin = sim::SimulatePartWall(config);
  WriteRunArchive(dir / "part.h5", twin.scan);
  const RunArchive places = ReadPartScan(dir / "part.h5", false, false);
  WorkerPool pool(2);
  ProfileStream stream(dir / "part.h5", pool);
  std::vector<part::PartGeometryRow> streamed;
  part::MeasurePart(stream, *places.part, twin.rig, {}, [&](const part::PartGeometryRow& r) { streamed.push_back(r); });
  const std::vector<part::PartGeometryRow> memory = Measure(twin.scan, twin.rig, true);
  ASSERT_EQ(streamed.size(), memory.size());
  for (std::size_t i = 0; i < memory.size(); ++i) {
    EXPECT_EQ(streamed[i].bead.area_mm2, memory[i].bead.area_mm2) << i;
    EXPECT_EQ(streamed[i].bead.shift_mm, memory[i].bead.shift_mm) << i;
  }
}

TEST(PartWall, ALayerMissingFromTheScanLeavesTheNextWithoutASurfaceBelow) {
  sim::PartTwinConfig config;
  config.layers = 4;
  config.length_mm = 20.0;
  sim::PartTwin twin = sim::SimulatePartWall(config);
  // Keep layers 0, 1 and 3: layer 2 was not scanned.
  RunArchive& s = twin.scan;
  RunArchive kept = s;
  kept.profiles.t_s.clear(), kept.profiles.encoder.clear(), kept.profiles.z_mm.clear();
  kept.part = PartPlaces{};
  const std::size_t p = s.profiles.points;
  for (std::size_t i = 0; i < s.profiles.size(); ++i) {
    if (s.part->layer[i] == 2) continue;
    kept.profiles.t_s.push_back(s.profiles.t_s[i]);
    kept.profiles.encoder.push_back(0);
    kept.profiles.z_mm.insert(kept.profiles.z_mm.end(), s.profiles.z_mm.begin() + i * p,
                              s.profiles.z_mm.begin() + (i + 1) * p);
    kept.part->layer.push_back(s.part->layer[i]);
    kept.part->path_mm.push_back(s.part->path_mm[i]);
    kept.part->frame_z_mm.push_back(s.part->frame_z_mm[i]);
    kept.part->frame_x_mm.push_back(s.part->frame_x_mm[i]);
  }
  int layer3 = 0;
  for (const auto& r : Measure(kept, twin.rig, true)) {
    if (r.layer != 3) {
      EXPECT_TRUE(r.bead.valid()) << r.profile;
      continue;
    }
    ++layer3;
    EXPECT_EQ(r.bead.status, part::AddedStatus::kNoSurfaceBelow);
    EXPECT_TRUE(std::isnan(r.bead.area_mm2));
  }
  EXPECT_GT(layer3, 30);
}

// A scan whose frame heights are not the head's: not given (bead import
// without --frame-z-column: 0 in every profile) while the profiler rose
// with the head, each layer's surface then a layer's rise under the one
// before it; or twice the head's (another unit, another axis), each
// layer's bare bed a rise over it. No row above the bed is measured, each
// says so, and by the rise: the surface under the old one over most of the
// profile, or the bare bed in the rig's reference areas off the old scan
// of it. The bed's layer, measured against its own reference line, is as
// before.
TEST(PartWall, AScanWhoseFrameHeightsAreNotTheHeadsIsNotMeasuredAboveTheBed) {
  sim::PartTwinConfig config;
  config.layers = 3;
  config.length_mm = 20.0;
  sim::PartTwin twin = sim::SimulatePartWall(config);
  const std::vector<part::PartGeometryRow> right = Measure(twin.scan, twin.rig, true);
  const PartPlaces& places = *twin.scan.part;
  std::vector<double> rise(config.layers, NAN);  // layer n's frame over layer n - 1's, mm
  for (std::size_t i = 0; i < places.size(); ++i) {
    const int64_t layer = places.layer[i];
    if (layer > 0 && std::isnan(rise[layer])) {
      // (The twin's frame rides the layer's base: one height in a layer.)
      const auto below = std::find(places.layer.begin(), places.layer.end(), layer - 1) - places.layer.begin();
      rise[layer] = places.frame_z_mm[i] - places.frame_z_mm[below];
    }
  }
  for (const bool doubled : {false, true}) {
    RunArchive wrong = twin.scan;
    for (double& z : wrong.part->frame_z_mm) z = doubled ? 2.0 * z - places.frame_z_mm.front() : 0.0;
    const std::vector<part::PartGeometryRow> rows = Measure(wrong, twin.rig, true);
    ASSERT_EQ(rows.size(), right.size());
    int above = 0;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const part::PartGeometryRow& r = rows[i];
      if (r.layer == 0) {
        // (Its heights moved by another frame height, in floats: 4e-6 mm a
        // point at 60 mm, 2.4e-5 mm^2 over the bead's 6 mm.)
        EXPECT_NEAR(r.bead.area_mm2, right[i].bead.area_mm2, 1e-4) << i;
        continue;
      }
      ++above;
      EXPECT_TRUE(right[i].bead.valid()) << i;
      // The median of hundreds of points (an area's, or those the surface lies under by), each
      // a rise off to two points' noise (0.014 mm): within a noise.
      if (doubled) {
        EXPECT_EQ(r.bead.status, part::AddedStatus::kBedMoved) << i;
        EXPECT_NEAR(r.bead.bed_off_mm, rise[r.layer], config.noise_mm) << i;
      } else {
        EXPECT_EQ(r.bead.status, part::AddedStatus::kUnderSurfaceBelow) << i;
        EXPECT_NEAR(r.bead.under_mm, -rise[r.layer], config.noise_mm) << i;
      }
    }
    EXPECT_GT(above, 60);
  }
  // Material laid in one reference area (a bead 1 mm high over its inner
  // half, in every layer above the bed) is no moved bed: the other area
  // stays where the layer below has it.
  RunArchive bumped = twin.scan;
  const ReferenceArea& area = twin.rig.reference_left;
  const double inner = 0.5 * (area.x_min_mm + area.x_max_mm);
  for (std::size_t i = 0; i < places.size(); ++i) {
    if (places.layer[i] == 0) continue;
    const ProfileView v = bumped.profiles.view(i);
    for (std::size_t k = 0; k < v.x_mm.size(); ++k)
      if (v.x_mm[k] > inner && area.Contains(v.x_mm[k])) bumped.profiles.z_mm[i * bumped.profiles.points + k] += 1.0f;
  }
  for (const part::PartGeometryRow& r : Measure(bumped, twin.rig, true))
    EXPECT_NE(r.bead.status, part::AddedStatus::kBedMoved) << r.profile;
}

}  // namespace
}  // namespace bead

namespace bead {
namespace {

// A profile whose x spans kilometres at the sensor's spacing is no bead's:
// its rows are invalid, and nothing the size of that span is allocated.
TEST(PartWall, AnXFarOutsideTheFieldIsRefusedNotAllocated) {
  sim::PartTwinConfig config;
  config.layers = 2;
  config.length_mm = 3.0;
  sim::PartTwin twin = sim::SimulatePartWall(config);
  twin.scan.profiles.x_mm.back() = 1e7f;  // shared by every profile
  ProfileStream stream("twin", twin.scan.profiles);
  int rows = 0;
  part::MeasurePart(stream, *twin.scan.part, twin.rig, {}, [&](const part::PartGeometryRow& r) {
    ++rows;
    EXPECT_FALSE(r.bead.valid()) << r.profile;
  });
  EXPECT_EQ(rows, static_cast<int>(twin.scan.profiles.size()));
}

}  // namespace
}  // namespace bead
