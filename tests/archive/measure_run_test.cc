// A run streamed window by window (MeasureRun) gives what the whole-archive
// path gives: every profile's geometry bit for bit (the same processor per
// profile), the pooled occlusion fitted on the same profiles, and the same
// per-profile fits in the 'each' mode, whatever the window and the threads.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "libbead/archive/measure_run.h"
#include "libbead/core/error.h"
#include "libbead/io/run_archive.h"
#include "libbead/occlusion/occlusion_pool.h"
#include "libbead/profile/measure_block.h"
#include "libbead/sim/rig_simulator.h"
#include "tests/support/temp_dir.h"
#include "tests/support/error_stats.h"

namespace bead {
namespace {

using test::SameBits;

struct Whole {
  std::vector<BeadGeometry> geometry;
  occlusion::PooledOcclusion pool;
};

class MeasureRunTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sim::SimConfig c;
    c.duration_s = 6;  // 1200 profiles of 640 points: several chunks of 102 rows
    c.seed = 11;
    sim_ = new sim::SimulatedRun(sim::Simulate(c));
    dir_ = new test::TempDir;
    WriteRunArchive(*dir_ / "run.h5", sim_->run);
  }
  static void TearDownTestSuite() {
    delete dir_;
    delete sim_;
  }
  static Whole MeasureWhole() {
    const ProfileBlock& b = sim_->run.profiles;
    Whole w;
    auto view = [&](std::size_t i) { return b.view(i); };
    w.geometry = MeasureProfiles(b.size(), view, sim_->rig_file.reference_left, sim_->rig_file.reference_right, {});
    occlusion::OcclusionOptions o;
    o.laser_origin = sim_->rig_file.laser_origin;
    w.pool = occlusion::PoolOcclusion(b.size(), view, w.geometry, o);
    return w;
  }
  static std::vector<GeometryRow> Stream(OcclusionMode mode, std::size_t window, unsigned threads,
                                         MeasureRunSummary* summary = nullptr) {
    WorkerPool pool(threads);
    ProfileStream stream(*dir_ / "run.h5", pool);
    MeasureRunOptions options;
    options.occlusion = mode;
    options.estimate = occlusion::EstimateOcclusion;
    options.window_rows = window;
    std::vector<GeometryRow> rows;
    const MeasureRunSummary s =
        MeasureRun(stream, sim_->rig_file, pool, options, [&](const GeometryRow& r) { rows.push_back(r); });
    if (summary) *summary = s;
    return rows;
  }
  static sim::SimulatedRun* sim_;
  static test::TempDir* dir_;
};
sim::SimulatedRun* MeasureRunTest::sim_ = nullptr;
test::TempDir* MeasureRunTest::dir_ = nullptr;

TEST_F(MeasureRunTest, StreamedGeometryAndPoolAreTheWholeArchives) {
  const Whole whole = MeasureWhole();
  ASSERT_TRUE(whole.pool.ok);
  for (const auto& [window, threads] : std::vector<std::pair<std::size_t, unsigned>>{{100, 1}, {4096, 2}, {250, 3}}) {
    MeasureRunSummary s;
    const std::vector<GeometryRow> rows = Stream(OcclusionMode::kPooled, window, threads, &s);
    ASSERT_EQ(rows.size(), whole.geometry.size());
    std::size_t valid = 0;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const BeadGeometry& a = rows[i].geometry;
      const BeadGeometry& b = whole.geometry[i];
      ASSERT_EQ(rows[i].profile, static_cast<int64_t>(i));
      ASSERT_EQ(a.status, b.status) << i;
      ASSERT_TRUE(SameBits(a.area_mm2, b.area_mm2) && SameBits(a.width_mm, b.width_mm) &&
                  SameBits(a.height_mm, b.height_mm) && SameBits(a.area_sigma_mm2, b.area_sigma_mm2) &&
                  SameBits(a.reference.residual_rms_mm, b.reference.residual_rms_mm))
          << "profile " << i << " window " << window;
      const occlusion::CorrectedArea c = occlusion::ApplyPooled(whole.pool, b);
      ASSERT_TRUE(SameBits(rows[i].area_corrected_mm2, c.area_mm2) &&
                  SameBits(rows[i].area_corrected_sigma_mm2, c.sigma_mm2))
          << i;
      valid += b.valid();
    }
    EXPECT_EQ(s.valid, valid);
    EXPECT_EQ(s.pooled.fitted, whole.pool.fitted);
    EXPECT_TRUE(SameBits(s.pooled.bias_fraction, whole.pool.bias_fraction));
    EXPECT_TRUE(SameBits(s.pooled.fraction_sigma, whole.pool.fraction_sigma));
  }
}

TEST_F(MeasureRunTest, FitsPerProfileDoNotDependOnThreads) {
  const std::vector<GeometryRow> one = Stream(OcclusionMode::kEach, 300, 1);
  const std::vector<GeometryRow> three = Stream(OcclusionMode::kEach, 300, 3);
  ASSERT_EQ(one.size(), three.size());
  std::size_t fitted = 0;
  for (std::size_t i = 0; i < one.size(); ++i) {
    ASSERT_TRUE(SameBits(one[i].area_corrected_mm2, three[i].area_corrected_mm2)) << i;
    fitted += std::isfinite(one[i].area_corrected_mm2);
  }
  EXPECT_GT(fitted, one.size() / 2);  // most profiles have a bead to fit
}

// A run in a pooled or fitted mode is handed its fit; none is a clear error.
TEST_F(MeasureRunTest, AFitModeWithoutItsEstimatorIsRefused) {
  WorkerPool pool(1);
  ProfileStream stream(*dir_ / "run.h5", pool);
  MeasureRunOptions options;  // occlusion pooled, no estimate
  try {
    MeasureRun(stream, sim_->rig_file, pool, options, [](const GeometryRow&) {});
    FAIL() << "measured without an occlusion fit";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("MeasureRunOptions::estimate"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace bead
