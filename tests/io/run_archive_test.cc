#include "libbead/io/run_archive.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "libbead/core/error.h"
#include "libbead/io/hdf5_file.h"
#include "tests/support/temp_dir.h"

namespace bead {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

RunArchive SmallRun(bool shared_x) {
  RunArchive run;
  auto& p = run.profiles;
  p.points = 4;
  p.shared_x = shared_x;
  for (int i = 0; i < 3; ++i) {
    p.t_s.push_back(0.005 * i);
    p.encoder.push_back(4294967290LL + 7 * i);  // near a 32-bit wrap
    for (int k = 0; k < 4; ++k) {
      if (!shared_x || i == 0) p.x_mm.push_back(k == 2 && !shared_x ? kNaN : -1.5f + k + 0.01f * i * !shared_x);
      p.z_mm.push_back(k == 1 ? kNaN : 0.25f * k + i);
    }
  }
  AcquisitionLog log;
  for (int i = 0; i < 5; ++i) {
    log.t_s.push_back(0.001 * i);
    log.encoder.push_back(100 + i);
    log.screw_rpm.push_back(60.0 + i);
    log.extruder_cmd_v.push_back(1.5);
  }
  log.wheel_cmd_v.assign(5, 2.0);
  run.log = log;
  run.attributes["material"] = "CF-ABS";
  run.attributes["nozzle_mm"] = "5.08";
  return run;
}

void ExpectSameFloats(const std::vector<float>& a, const std::vector<float>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::isnan(a[i]))
      EXPECT_TRUE(std::isnan(b[i])) << i;
    else
      EXPECT_EQ(a[i], b[i]) << i;
  }
}

TEST(RunArchive, RoundTripsBothXLayoutsLogAndAttributes) {
  test::TempDir dir;
  for (bool shared : {true, false}) {
    const RunArchive run = SmallRun(shared);
    const std::string path = dir / (shared ? "shared.h5" : "per_profile.h5");
    WriteRunArchive(path, run);
    const RunArchive back = ReadRunArchive(path);
    EXPECT_EQ(back.profiles.shared_x, shared);
    EXPECT_EQ(back.profiles.points, 4u);
    EXPECT_EQ(back.profiles.t_s, run.profiles.t_s);
    EXPECT_EQ(back.profiles.encoder, run.profiles.encoder);
    ExpectSameFloats(back.profiles.x_mm, run.profiles.x_mm);
    ExpectSameFloats(back.profiles.z_mm, run.profiles.z_mm);
    ASSERT_TRUE(back.log.has_value());
    EXPECT_EQ(back.log->screw_rpm, run.log->screw_rpm);
    EXPECT_EQ(back.log->wheel_cmd_v, run.log->wheel_cmd_v);
    EXPECT_EQ(back.attributes.at("material"), "CF-ABS");
    const ProfileView v = back.profiles.view(2);
    EXPECT_EQ(v.encoder, 4294967304LL);
    EXPECT_FLOAT_EQ(v.z_mm[3], 2.75f);
  }
}

TEST(RunArchive, LogIsOptional) {
  test::TempDir dir;
  RunArchive run = SmallRun(true);
  run.log.reset();
  WriteRunArchive(dir / "profiles_only.h5", run);
  EXPECT_FALSE(ReadRunArchive(dir / "profiles_only.h5").log.has_value());
}

// Acquisition software records more than the spec's five log datasets:
// every other float [M] dataset under /log is a channel, its unit from a
// string attribute `unit`; what is not a float vector of the log's length
// (an integer counter, a vector of another length) is left alone.
TEST(RunArchive, RecordedLogChannelsRoundTripWithTheirUnits) {
  test::TempDir dir;
  RunArchive run = SmallRun(true);
  run.log->channels.push_back({"barrel_temp_c", "C", {199.5, 200.0, 200.5, 201.0, 200.0}});
  run.log->channels.push_back({"melt_pressure", "", {10, 11, 12, 13, 14}});
  const std::string path = dir / "channels.h5";
  WriteRunArchive(path, run);
  {  // another tool's extras beside them
    h5::File f = h5::File::OpenReadWrite(path);
    f.Write("/log/heater_cycles", std::vector<int64_t>{1, 1, 2, 2, 3}, {5});
    f.Write("/log/calibration", std::vector<double>{1.0, 2.0}, {2});
  }
  const RunArchive back = ReadRunArchive(path);
  ASSERT_TRUE(back.log.has_value());
  ASSERT_EQ(back.log->channels.size(), 2u);
  EXPECT_EQ(back.log->channels[0].name, "barrel_temp_c");
  EXPECT_EQ(back.log->channels[0].unit, "C");
  EXPECT_EQ(back.log->channels[0].values, run.log->channels[0].values);
  EXPECT_EQ(back.log->channels[1].name, "melt_pressure");
  EXPECT_EQ(back.log->channels[1].unit, "");
}

TEST(RunArchive, AChannelOfTheWrongLengthOrNameIsRefusedByTheWriter) {
  test::TempDir dir;
  RunArchive run = SmallRun(true);
  run.log->channels.push_back({"barrel_temp_c", "C", {199.5, 200.0}});
  EXPECT_THROW(WriteRunArchive(dir / "short.h5", run), Error);
  run.log->channels.back() = {"screw_rpm", "", std::vector<double>(5, 1.0)};
  EXPECT_THROW(WriteRunArchive(dir / "spec_name.h5", run), Error);
}

// A part scan (format 1.1: root attribute kind = "part") is said as such,
// never measured as if it were a run on the wheel.
TEST(RunArchive, APartScanIsNamedAndRefused) {
  test::TempDir dir;
  RunArchive run = SmallRun(true);
  run.attributes["kind"] = "part";
  WriteRunArchive(dir / "part.h5", run);
  try {
    ReadRunArchive(dir / "part.h5");
    ADD_FAILURE() << "a part scan was read as a run";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("part.h5: is a part scan (root attribute kind = \"part\""), std::string::npos)
        << e.what();
  }
}

TEST(PinScanArchive, RoundTrips) {
  test::TempDir dir;
  PinScanArchive pins;
  for (int k = 0; k < 3; ++k) pins.scans.push_back({1000 + 13 * k, SmallRun(true).profiles});
  WritePinScanArchive(dir / "pins.h5", pins);
  const PinScanArchive back = ReadPinScanArchive(dir / "pins.h5");
  ASSERT_EQ(back.scans.size(), 3u);
  EXPECT_EQ(back.scans[2].start_encoder, 1026);
  EXPECT_EQ(back.scans[1].profiles.t_s, pins.scans[1].profiles.t_s);
  // A run archive is not a pin-scan archive, and says so; nor the reverse.
  WriteRunArchive(dir / "run.h5", SmallRun(true));
  try {
    ReadPinScanArchive(dir / "run.h5");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(
        std::string(e.what()).find("run.h5: is a run archive (it holds /profiles): this takes a pin-scan archive"),
        std::string::npos)
        << e.what();
  }
  try {
    ReadRunArchive(dir / "pins.h5");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("pins.h5: is a pin-scan archive (it holds /scans): this command takes a run "
                                         "archive"),
              std::string::npos)
        << e.what();
  }
}

TEST(RunArchive, WriterRefusesInconsistentBlocksAndKeepsTheOldFile) {
  test::TempDir dir;
  const std::string path = dir / "run.h5";
  WriteRunArchive(path, SmallRun(true));
  RunArchive bad = SmallRun(true);
  bad.profiles.t_s[2] = bad.profiles.t_s[1];
  EXPECT_THROW(WriteRunArchive(path, bad), Error);
  EXPECT_EQ(ReadRunArchive(path).profiles.size(), 3u);  // the old file is intact
}

}  // namespace
}  // namespace bead
