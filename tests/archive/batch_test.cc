// bead batch: killed at random moments and started again it ends with the
// files an uninterrupted batch writes, byte for byte, and no temporary
// left; shards cover every run once; a run that fails does not stop the
// others. And the single-file commands (measure, flow, explain -o): a kill
// leaves the previous file or the new one whole, never a part.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <random>
#include <regex>

#include "libbead/archive/batch_runs.h"
#include "libbead/core/error.h"
#include "libbead/sim/rig_simulator.h"
#include "libbead/sim/sim_writer.h"
#include "tests/support/kill_harness.h"
#include "tests/support/run_cli.h"

namespace bead {
namespace {
namespace fs = std::filesystem;

// Every file under `dir` (by path relative to it) with its bytes.
std::map<std::string, std::string> Tree(const std::string& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = test::ReadText(e.path().string());
  return files;
}

class BatchTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir;
    for (int k = 0; k < 3; ++k) {
      sim::SimConfig c;
      c.seed = 100 + k;
      c.duration_s = 3;
      c.pins.scans = 1;
      sim::WriteSimulatedRun(*dir_ / ("r" + std::to_string(k)), sim::Simulate(c));
    }
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string Runs() {
    std::string s;
    for (int k = 0; k < 3; ++k) s += " " + *dir_ / ("r" + std::to_string(k) + "/run.h5");
    return s;
  }
  static std::string Batch(const std::string& out, const std::string& extra = "") {
    return std::string(BEAD_CLI) + " batch --rig " + *dir_ / "r0/rig.yaml" + " -o " + out + extra + Runs();
  }
  static test::TempDir* dir_;
};
test::TempDir* BatchTest::dir_ = nullptr;

TEST_F(BatchTest, KilledAndStartedAgainItEndsAsAnUninterruptedBatch) {
  test::TempDir out;
  int status = 0;
  const double full = test::TimeCommand(Batch(out / "whole"), &status);
  ASSERT_EQ(status, 0);
  const auto whole = Tree(out / "whole");
  ASSERT_EQ(whole.count("summary.csv"), 1u);
  ASSERT_EQ(whole.count("r1_run/flow.csv"), 1u);

  std::mt19937 rng(20261123);
  std::uniform_real_distribution<double> when(0.0, full);
  int kills = 0, attempts = 0;
  while (attempts < 12 && test::RunKilledAfter(Batch(out / "cut"), when(rng)) == -1) ++kills, ++attempts;
  ASSERT_EQ(test::RunKilledAfter(Batch(out / "cut"), 1e9), 0);  // the same command, to its end
  EXPECT_GT(kills, 0) << "no kill landed while the batch ran: the test tested nothing";
  EXPECT_EQ(test::CountTemporaries(out / "cut"), 0);
  const auto cut = Tree(out / "cut");
  ASSERT_EQ(cut.size(), whole.size());
  for (const auto& [path, bytes] : whole) EXPECT_TRUE(cut.count(path) && cut.at(path) == bytes) << path;
}

TEST_F(BatchTest, ShardsCoverEveryRunOnceAndTheLastSummaryHasThemAll) {
  test::TempDir out;
  auto [s1, text1] =
      test::RunCli(out, "batch --shard 1/2 --rig " + *dir_ / "r0/rig.yaml" + " -o " + out / "o" + Runs());
  ASSERT_EQ(s1, 0) << text1;
  auto [s2, text2] =
      test::RunCli(out, "batch --shard 2/2 --rig " + *dir_ / "r0/rig.yaml" + " -o " + out / "o" + Runs());
  ASSERT_EQ(s2, 0) << text2;
  const std::regex done(R"(\] (r\d_run): \d+ profiles)");
  std::map<std::string, int> measured;
  for (const std::string* t : {&text1, &text2})
    for (std::sregex_iterator it(t->begin(), t->end(), done), end; it != end; ++it) ++measured[(*it)[1]];
  EXPECT_EQ(measured, (std::map<std::string, int>{{"r0_run", 1}, {"r1_run", 1}, {"r2_run", 1}}));
  const std::string summary = test::ReadText(out / "o/summary.csv");
  for (const char* name : {"r0_run,", "r1_run,", "r2_run,"}) EXPECT_NE(summary.find(name), std::string::npos) << name;
}

TEST_F(BatchTest, AFailedRunIsReportedAndTheOthersGoOn) {
  test::TempDir out;
  test::WriteText(out / "broken.h5", "not an HDF5 file");
  auto [status, text] = test::RunCli(out, "batch --rig " + *dir_ / "r0/rig.yaml" + " -o " + out / "o " +
                                              out / "broken.h5" + " " + *dir_ / "r2/run.h5");
  EXPECT_EQ(status, 1) << text;
  const std::string summary = test::ReadText(out / "o/summary.csv");
  EXPECT_NE(summary.find("broken,"), std::string::npos) << summary;
  EXPECT_NE(summary.find(",failed: "), std::string::npos) << summary;
  EXPECT_NE(summary.find("run," + *dir_ / "r2/run.h5"), std::string::npos) << summary;
  EXPECT_TRUE(fs::exists(out / "o/run/flow.csv"));
}

TEST(BatchShard, TakenFromTheOptionSlurmOrMpirun) {
  using Env = std::map<std::string, std::string>;
  auto resolve = [](const std::string& option, const Env& env) {
    return ResolveShard(option, [&](const char* k) { return env.count(k) ? env.at(k).c_str() : nullptr; });
  };
  Shard s = resolve("3/4", {{"OMPI_COMM_WORLD_RANK", "0"}, {"OMPI_COMM_WORLD_SIZE", "2"}});
  EXPECT_EQ(s.index, 2u);  // the option wins
  EXPECT_EQ(s.count, 4u);
  // --array=10-20:5 has tasks 10, 15, 20: task 15 is the second of three.
  s = resolve("", {{"SLURM_ARRAY_TASK_ID", "15"},
                   {"SLURM_ARRAY_TASK_MIN", "10"},
                   {"SLURM_ARRAY_TASK_STEP", "5"},
                   {"SLURM_ARRAY_TASK_COUNT", "3"}});
  EXPECT_EQ(s.index, 1u);
  EXPECT_EQ(s.count, 3u);
  s = resolve("", {{"PMI_RANK", "3"}, {"PMI_SIZE", "4"}});
  EXPECT_EQ(s.index, 3u);
  s = resolve("", {});
  EXPECT_EQ(s.count, 1u);
  EXPECT_TRUE(s.Takes(7));
  EXPECT_THROW(resolve("0/4", {}), Error);
  EXPECT_THROW(resolve("5/4", {}), Error);
  EXPECT_THROW(resolve("", {{"OMPI_COMM_WORLD_RANK", "2"}, {"OMPI_COMM_WORLD_SIZE", "2"}}), Error);
}

TEST(BatchRuns, RepeatedStemsAreNamedByTheirFoldersAndARunListedTwiceIsRefused) {
  const std::vector<BatchRun> runs =
      RunsFromPaths({"/d/day1/a/run.h5", "/d/day1/b/run.h5", "/d/day2/x.h5"}, "rig.yaml");
  EXPECT_EQ(runs[0].name, "day1_a_run");
  EXPECT_EQ(runs[1].name, "day1_b_run");
  EXPECT_EQ(runs[2].name, "x");
  EXPECT_THROW(RunsFromPaths({"/d/a/run.h5", "/d/a/run.h5"}, "rig.yaml"), Error);
}

// measure, flow and explain -o over a file that was there before.
class InterruptedWriteTest : public BatchTest {
 protected:
  void ExpectOldOrNewWhole(const std::string& command_without_output) {
    test::TempDir out;
    int status = 0;
    const double full = test::TimeCommand(command_without_output + " -o " + out / "new.out", &status);
    ASSERT_EQ(status, 0);
    const std::string fresh = test::ReadText(out / "new.out");
    const std::string previous = "the user's previous result\n";
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> when(0.0, full);
    int kills = 0;
    for (int attempt = 0; attempt < 8; ++attempt) {
      test::WriteText(out / "result.out", previous);
      kills += test::RunKilledAfter(command_without_output + " -o " + out / "result.out", when(rng)) == -1;
      const std::string now = test::ReadText(out / "result.out");
      EXPECT_TRUE(now == previous || now == fresh) << "attempt " << attempt << ": a partial file";
    }
    EXPECT_GT(kills, 0);
    ASSERT_EQ(test::RunKilledAfter(command_without_output + " -o " + out / "result.out", 1e9), 0);
    EXPECT_EQ(test::ReadText(out / "result.out"), fresh);
    EXPECT_EQ(test::CountTemporaries(out.path().string()), 0) << "temporaries of killed runs pile up";
  }
};

TEST_F(InterruptedWriteTest, Measure) {
  ExpectOldOrNewWhole(std::string(BEAD_CLI) + " measure --rig " + *dir_ / "r0/rig.yaml " + *dir_ / "r0/run.h5");
}
TEST_F(InterruptedWriteTest, Flow) {
  ExpectOldOrNewWhole(std::string(BEAD_CLI) + " flow --rig " + *dir_ / "r0/rig.yaml " + *dir_ / "r0/run.h5");
}
TEST_F(InterruptedWriteTest, ExplainOut) {
  ExpectOldOrNewWhole(std::string(BEAD_CLI) + " explain --max-effects 1 --rig " + *dir_ / "r1/rig.yaml " +
                      *dir_ / "r1/run.h5");
}

}  // namespace
}  // namespace bead
