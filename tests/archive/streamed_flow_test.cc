// A run's flow streamed in fixed memory (StreamRunFlow) is the whole-run
// flow (MeasureWholeRun + ComputeFlow) bit for bit: every sample, the
// total volume, the filters' counts and the warnings; where the history it
// keeps is too short for the run it says so instead of guessing. And the
// medians it takes by walking a sequence again are MedianInPlace's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <random>

#include "libbead/archive/batch.h"
#include "libbead/archive/measured_run.h"
#include "libbead/archive/run_flow.h"
#include "libbead/archive/streamed_flow.h"
#include "libbead/core/error.h"
#include "libbead/core/median.h"
#include "libbead/core/median_by_walks.h"
#include "libbead/io/flow_csv.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/io/run_archive.h"
#include "libbead/occlusion/occlusion_fit.h"
#include "libbead/sim/rig_simulator.h"
#include "tests/support/temp_dir.h"
#include "tests/support/error_stats.h"

namespace bead {
namespace {

using test::SameBits;

TEST(MedianByWalks, IsMedianInPlaceBitForBit) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal(0.0, 3.0);
  for (const std::size_t n : {1, 2, 3, 10, 1001, 4096, 50000}) {
    std::vector<double> v(n);
    for (double& x : v) x = normal(rng);
    for (std::size_t i = 0; i < n / 3; ++i) v[i] = v[n - 1 - i];  // repeated values
    if (n > 4) v[1] = -0.0, v[2] = 0.0, v[3] = 1e-310;            // signed zeros, a subnormal
    std::vector<double> copy = v;
    copy.push_back(NAN);  // skipped by the walk, not a value
    const double walked = MedianByWalks([&](const std::function<void(double)>& visit) {
      for (double x : copy) visit(x);
    });
    std::vector<double> sorted = v;
    EXPECT_TRUE(SameBits(walked, MedianInPlace(sorted.data(), sorted.size()))) << n;
  }
  EXPECT_TRUE(std::isnan(MedianByWalks([](const std::function<void(double)>&) {})));
}

// Sequences longer than what is gathered in memory (kCollectAtMost): one
// clustered closely (the top bits alike: the second walk narrows it), one
// nearly a single value (no walk narrows it below the cap: four
// histograms). Walked together, each median is the one found alone, and no
// more than four walks are taken.
TEST(MedianByWalks, LongSequencesTogetherInAtMostFourWalks) {
  const std::size_t n = 2 * kCollectAtMost + 2;  // even: two middle values
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> near_one(1.0, 1.01);
  std::vector<double> clustered(n), constant(n, 2e-3);
  for (double& x : clustered) x = near_one(rng);
  for (std::size_t i = 0; i < n / 4; ++i) constant[i] = 2e-3 + 1e-9 * static_cast<double>(i % 7);
  int walks = 0;
  const std::vector<double> m = MediansByWalks(2, [&](const std::function<void(int, double)>& visit) {
    ++walks;
    for (std::size_t i = 0; i < n; ++i) visit(0, clustered[i]), visit(1, constant[i]);
  });
  EXPECT_LE(walks, 4);
  for (auto [sequence, values] : {std::pair{0, clustered}, std::pair{1, constant}}) {
    std::vector<double> copy = values;
    EXPECT_TRUE(SameBits(m[static_cast<std::size_t>(sequence)], MedianInPlace(copy.data(), copy.size()))) << sequence;
  }
}

class StreamedFlowTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sim::SimConfig c;
    c.duration_s = 8;
    c.seed = 3;
    c.encoder.missed_read_prob = 0.01;
    sim_ = new sim::SimulatedRun(sim::Simulate(c));
    // Glitches the twin does not make: single reads 400 counts off.
    AcquisitionLog& log = *sim_->run.log;
    for (std::size_t i = 500; i + 1 < log.size(); i += 997) log.encoder[i] += 400;
    dir_ = new test::TempDir;
    WriteRunArchive(*dir_ / "run.h5", sim_->run);
  }
  static void TearDownTestSuite() {
    delete dir_;
    delete sim_;
  }
  static MeasureRunOptions Measure(std::size_t window) {
    MeasureRunOptions o;
    o.occlusion = OcclusionMode::kPooled;
    o.estimate = occlusion::EstimateOcclusion;
    o.window_rows = window;
    return o;
  }
  static sim::SimulatedRun* sim_;
  static test::TempDir* dir_;
};
sim::SimulatedRun* StreamedFlowTest::sim_ = nullptr;
test::TempDir* StreamedFlowTest::dir_ = nullptr;

TEST_F(StreamedFlowTest, IsTheWholeRunsFlowBitForBit) {
  const std::string path = *dir_ / "run.h5";
  const Rig& rig = sim_->rig_file;
  WorkerPool pool(2);
  const MeasuredRun m = MeasureWholeRun(OpenRun(path, pool), rig, pool, Measure(4096));
  const FlowResult whole = ComputeFlow(rig, m.run.profiles, m.geometry, *m.run.log, {}, m.corrected, m.sigma);
  ASSERT_GT(whole.encoder_repairs, 10);  // the missed reads and the glitches were there to repair
  // Windows of 250 profiles; 3 s of log kept on an 8 s run: the log is let go as it streams.
  std::vector<FlowSample> got;
  std::vector<GeometryRow> rows;
  const StreamedFlow s = StreamRunFlow(
      OpenRun(path, pool, false), path, rig, pool, Measure(250), {}, [&](const FlowSample& f) { got.push_back(f); },
      [&](const GeometryRow& r) { rows.push_back(r); }, 3.0);
  ASSERT_TRUE(s.complete);
  ASSERT_EQ(got.size(), whole.samples.size());
  ASSERT_EQ(rows.size(), whole.samples.size());
  std::size_t valid = 0;
  for (std::size_t k = 0; k < got.size(); ++k) {
    const FlowSample& a = got[k];
    const FlowSample& b = whole.samples[k];
    ASSERT_EQ(a.profile, b.profile);
    ASSERT_EQ(a.valid, b.valid) << k;
    ASSERT_EQ(a.encoder, b.encoder) << k;
    ASSERT_TRUE(SameBits(a.t_s, b.t_s) && SameBits(a.surface_speed_mm_s, b.surface_speed_mm_s) &&
                SameBits(a.area_mm2, b.area_mm2) && SameBits(a.area_corrected_mm2, b.area_corrected_mm2) &&
                SameBits(a.occlusion_bias_mm2, b.occlusion_bias_mm2) &&
                SameBits(a.area_corrected_sigma_mm2, b.area_corrected_sigma_mm2) &&
                SameBits(a.flow_mm3_s, b.flow_mm3_s) && SameBits(a.flow_sigma_mm3_s, b.flow_sigma_mm3_s) &&
                SameBits(a.screw_rpm, b.screw_rpm))
        << "sample " << k;
    ASSERT_TRUE(SameBits(rows[k].geometry.area_mm2, m.geometry[k].area_mm2)) << k;
    valid += b.valid;
  }
  EXPECT_GT(valid, got.size() / 2);
  EXPECT_EQ(s.valid, valid);
  EXPECT_TRUE(SameBits(s.total_volume_mm3, whole.total_volume_mm3));
  EXPECT_EQ(s.area_outliers, whole.area_outliers);
  EXPECT_EQ(s.speed_outliers, whole.speed_outliers);
  EXPECT_EQ(s.encoder_repairs, whole.encoder_repairs);
  EXPECT_EQ(s.warnings, whole.warnings);
  EXPECT_EQ(s.measure.valid, m.summary.valid);
}

// Kept history shorter than the nozzle-to-laser travel: with the laser
// half a turn further on (2 s at the twin's 15 RPM) and 1 s of log kept,
// the extrusion times fall out of it, and the stream says it is not the
// whole run's flow rather than hand on NaN for them. With 3 s kept it is.
TEST_F(StreamedFlowTest, AHistoryShorterThanTheTravelIsNotTakenForTheFlow) {
  const std::string path = *dir_ / "run.h5";
  Rig rig = sim_->rig_file;
  rig.offset_counts += rig.encoder.counts_per_rev / 2.0;
  WorkerPool pool(2);
  std::size_t valid = 0;
  const StreamedFlow s = StreamRunFlow(
      OpenRun(path, pool, false), path, rig, pool, Measure(4096), {}, [&](const FlowSample& f) { valid += f.valid; },
      {}, 1.0);
  EXPECT_FALSE(s.complete);
  EXPECT_NE(s.why.find("more than 1 s before they were measured"), std::string::npos) << s.why;
  const StreamedFlow enough = StreamRunFlow(
      OpenRun(path, pool, false), path, rig, pool, Measure(4096), {}, [](const FlowSample&) {}, {}, 3.0);
  EXPECT_TRUE(enough.complete);
  EXPECT_TRUE(enough.why.empty()) << enough.why;
  EXPECT_GT(enough.valid, valid);  // what the short history lost
}

// A log shorter than the speed's Savitzky-Golay window (the batch narrows
// the window to the log): the stream leaves the run to the whole-run path
// and says why; the batch takes that path by itself, its flow.csv is the
// whole-run flow's byte for byte and its summary row says what happened.
TEST_F(StreamedFlowTest, ALogShorterThanTheSpeedWindowTakesTheWholeRunPath) {
  RunArchive cut = sim_->run;
  AcquisitionLog& log = *cut.log;
  const double dt = log.t_s[1] - log.t_s[0];
  const int window = SpeedWindowSamples({}, dt);
  ASSERT_GT(window, 5);
  const std::size_t keep = static_cast<std::size_t>(window) - 2;
  const std::size_t from = log.size() / 2;  // the middle of the run, where profiles were measured
  for (auto* v : {&log.t_s, &log.screw_rpm, &log.extruder_cmd_v, &log.wheel_cmd_v})
    if (!v->empty()) *v = std::vector<double>(v->begin() + from, v->begin() + from + keep);
  log.encoder = std::vector<int64_t>(log.encoder.begin() + from, log.encoder.begin() + from + keep);
  const std::string path = *dir_ / "short_log.h5", rig_path = *dir_ / "rig.yaml";
  WriteRunArchive(path, cut);
  WriteRigFile(rig_path, MakeRigFile(sim_->rig_file));
  WorkerPool pool(2);
  const StreamedFlow s = StreamRunFlow(OpenRun(path, pool, false), path, sim_->rig_file, pool, Measure(4096), {},
                                       [](const FlowSample&) {});
  EXPECT_FALSE(s.complete);
  EXPECT_NE(s.why.find("the log's " + std::to_string(keep) + " samples are fewer than the speed window's " +
                       std::to_string(window)),
            std::string::npos)
      << s.why;

  BatchOptions options;
  options.out = *dir_ / "batch";
  options.estimate = occlusion::EstimateOcclusion;
  const RunResult r = ProcessRun({path, rig_path, "short_log"}, options, pool);
  ASSERT_TRUE(r.ok()) << r.status;
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("the flow was computed on the whole run in memory: the log's"), std::string::npos)
      << r.warnings[0];
  const MeasuredRun m = MeasureWholeRun(OpenRun(path, pool), sim_->rig_file, pool, Measure(4096));
  const FlowResult whole =
      ComputeFlow(sim_->rig_file, m.run.profiles, m.geometry, *m.run.log, {}, m.corrected, m.sigma);
  std::size_t valid = 0;
  for (const FlowSample& f : whole.samples) valid += f.valid;
  EXPECT_GT(valid, 0u);  // profiles inside the short log have a flow
  EXPECT_EQ(r.flow_samples, valid);
  WriteFlowCsv(*dir_ / "whole_flow.csv", whole);
  auto text = [](const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  EXPECT_EQ(text(options.out + "/short_log/flow.csv"), text(*dir_ / "whole_flow.csv"));
}

// What the flow cannot do without is named, as the whole-run path names it.
TEST_F(StreamedFlowTest, ARunWithoutItsLogIsNamed) {
  RunArchive bare = sim_->run;
  bare.log.reset();
  const std::string path = *dir_ / "bare.h5";
  WriteRunArchive(path, bare);
  WorkerPool pool(1);
  try {
    StreamRunFlow(OpenRun(path, pool, false), path, sim_->rig_file, pool, Measure(4096), {}, [](const FlowSample&) {});
    FAIL() << "a flow without a log";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/log: missing: the flow needs the acquisition log"), std::string::npos)
        << e.what();
  }
}

// The one call the commands use: streamed, it writes the flow CSV the
// whole-run path writes when asked to keep the run, byte for byte, and
// the same figures; a run without its log gives its geometry and says why
// there is no flow, or refuses when the flow is required.
TEST_F(StreamedFlowTest, MeasureRunFlowStreamedOrKeptWritesTheSameFiles) {
  const std::string path = *dir_ / "run.h5";
  WorkerPool pool(2);
  RunFlowRequest request;
  request.measure = Measure(250);
  request.flow_csv = *dir_ / "call_streamed_flow.csv";
  request.geometry_csv = *dir_ / "call_streamed_geometry.csv";
  const RunFlow streamed = MeasureRunFlow(path, sim_->rig_file, pool, request);
  request.keep = true;
  request.flow_csv = *dir_ / "call_kept_flow.csv";
  request.geometry_csv = *dir_ / "call_kept_geometry.csv";
  const RunFlow kept = MeasureRunFlow(path, sim_->rig_file, pool, request);
  EXPECT_TRUE(streamed.streamed);
  EXPECT_FALSE(kept.streamed);
  ASSERT_EQ(kept.flow.samples.size(), kept.whole.geometry.size());
  auto text = [](const std::string& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  EXPECT_FALSE(text(*dir_ / "call_kept_flow.csv").empty());
  EXPECT_EQ(text(*dir_ / "call_streamed_flow.csv"), text(*dir_ / "call_kept_flow.csv"));
  EXPECT_EQ(text(*dir_ / "call_streamed_geometry.csv"), text(*dir_ / "call_kept_geometry.csv"));
  EXPECT_EQ(streamed.valid, kept.valid);
  EXPECT_TRUE(SameBits(streamed.total_volume_mm3, kept.total_volume_mm3));
  EXPECT_EQ(streamed.encoder_repairs, kept.encoder_repairs);

  RunArchive bare = sim_->run;
  bare.log.reset();
  const std::string bare_path = *dir_ / "bare_call.h5";
  WriteRunArchive(bare_path, bare);
  request.keep = false;
  request.require_motion = false;
  request.flow_csv = *dir_ / "bare_flow.csv";
  request.geometry_csv = *dir_ / "bare_geometry.csv";
  const RunFlow geometry_only = MeasureRunFlow(bare_path, sim_->rig_file, pool, request);
  EXPECT_FALSE(geometry_only.gap.none());
  EXPECT_NE(geometry_only.gap.why.find("acquisition log"), std::string::npos) << geometry_only.gap.why;
  EXPECT_EQ(geometry_only.measure.profiles, sim_->run.profiles.size());
  EXPECT_EQ(text(*dir_ / "bare_geometry.csv"), text(*dir_ / "call_kept_geometry.csv"));
  EXPECT_FALSE(std::filesystem::exists(*dir_ / "bare_flow.csv"));
  request.require_motion = true;
  EXPECT_THROW(MeasureRunFlow(bare_path, sim_->rig_file, pool, request), Error);
}

// The scratch file goes where TMPDIR says; a folder that is not there is
// named, with the way out, before anything is measured.
TEST_F(StreamedFlowTest, AScratchFolderThatIsNotThereIsNamed) {
  const std::string path = *dir_ / "run.h5";
  const char* before = std::getenv("TMPDIR");
  const std::string saved = before ? before : "";
  const std::string missing = *dir_ / "no-such-folder";
  setenv("TMPDIR", missing.c_str(), 1);
  WorkerPool pool(1);
  std::string message;
  try {
    StreamRunFlow(OpenRun(path, pool, false), path, sim_->rig_file, pool, Measure(4096), {}, [](const FlowSample&) {});
  } catch (const Error& e) {
    message = e.what();
  }
  if (before)
    setenv("TMPDIR", saved.c_str(), 1);
  else
    unsetenv("TMPDIR");
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find(missing + " (set TMPDIR to a writable folder)"), std::string::npos) << message;
}

}  // namespace
}  // namespace bead
