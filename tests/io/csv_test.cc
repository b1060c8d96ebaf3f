#include <gtest/gtest.h>

#include <cmath>

#include "libbead/core/error.h"
#include "libbead/io/csv_reader.h"
#include "libbead/io/geometry_csv.h"
#include "libbead/io/profiles_csv.h"
#include "tests/support/temp_dir.h"

namespace bead {
namespace {

TEST(ProfilesCsv, ReadsLongFormWithMissingPointsAndUnevenLengths) {
  test::TempDir dir;
  test::WriteText(dir / "p.csv",
                  "profile,t_s,encoder,x_mm,z_mm\n"
                  "0,0.000,100,-1.0,0.5\n"
                  "0,0.000,100,0.0,\n"
                  "0,0.000,100,1.0,0.7\n"
                  "\n"
                  "1,0.005,104,-1.0,0.6\r\n"
                  "1,0.005,104,0.5,0.8\n");
  const ProfileBlock b = ReadProfilesCsv(dir / "p.csv");
  ASSERT_EQ(b.size(), 2u);
  EXPECT_EQ(b.points, 3u);
  EXPECT_FALSE(b.shared_x);
  EXPECT_EQ(b.encoder[1], 104);
  const ProfileView v0 = b.view(0), v1 = b.view(1);
  EXPECT_TRUE(std::isnan(v0.z_mm[1]));
  EXPECT_FLOAT_EQ(v1.x_mm[1], 0.5f);
  EXPECT_TRUE(std::isnan(v1.z_mm[2]));  // padding
  // Written and read back, it is the same block.
  WriteProfilesCsv(dir / "q.csv", b);
  const ProfileBlock c = ReadProfilesCsv(dir / "q.csv");
  EXPECT_EQ(c.t_s, b.t_s);
  EXPECT_EQ(c.points, b.points);
}

TEST(LogCsv, RoundTripsWithAndWithoutCommands) {
  test::TempDir dir;
  AcquisitionLog log;
  log.t_s = {0.0, 0.001, 0.002};
  log.encoder = {5, 9, 14};
  log.screw_rpm = {10.5, 11.0, 11.25};
  WriteLogCsv(dir / "a.csv", log);
  EXPECT_EQ(ReadLogCsv(dir / "a.csv").screw_rpm, log.screw_rpm);
  log.extruder_cmd_v = {1, 2, 3};
  log.wheel_cmd_v = {4, 5, 6};
  WriteLogCsv(dir / "b.csv", log);
  const AcquisitionLog back = ReadLogCsv(dir / "b.csv");
  EXPECT_EQ(back.wheel_cmd_v, log.wheel_cmd_v);
  EXPECT_EQ(back.encoder, log.encoder);
}

TEST(PinScansCsv, GroupsRowsByScan) {
  test::TempDir dir;
  test::WriteText(dir / "pins.csv",
                  "scan,start_encoder,profile,t_s,encoder,x_mm,z_mm\n"
                  "0,1000,0,0.0,4000,-1,0\n0,1000,0,0.0,4000,1,0\n0,1000,1,0.005,4003,-1,0\n0,1000,1,0.005,4003,1,2\n"
                  "1,1010,0,9.0,4010,-1,0\n1,1010,0,9.0,4010,1,0\n");
  const PinScanArchive pins = ReadPinScansCsv(dir / "pins.csv");
  ASSERT_EQ(pins.scans.size(), 2u);
  EXPECT_EQ(pins.scans[0].start_encoder, 1000);
  EXPECT_EQ(pins.scans[0].profiles.size(), 2u);
  EXPECT_EQ(pins.scans[1].profiles.encoder[0], 4010);
}

TEST(GeometryCsv, SpecColumnsFirstAndInvalidRowsKept) {
  test::TempDir dir;
  GeometryRow ok;
  ok.profile = 0;
  ok.t_s = 0.25;
  ok.encoder = 12;
  ok.geometry.status = ProfileStatus::kValid;
  ok.geometry.area_mm2 = 20.5;
  ok.geometry.width_mm = 10;
  ok.geometry.height_mm = 2;
  GeometryRow bad = ok;
  bad.profile = 1;
  bad.geometry.status = ProfileStatus::kNoReference;
  WriteGeometryCsv(dir / "g.csv", {ok, bad});
  const std::string text = test::ReadText(dir / "g.csv");
  EXPECT_EQ(text.rfind("profile,t_s,encoder,area_mm2,width_mm,height_mm,area_corrected_mm2,valid,", 0), 0u);
  EXPECT_NE(text.find("\n0,0.25,12,20.5,10,2,,1,"), std::string::npos) << text;
  EXPECT_NE(text.find("\n1,0.25,12,,,,,0,"), std::string::npos) << text;
  EXPECT_NE(text.find("no_reference"), std::string::npos);
}

TEST(CsvNumber, ShortestRoundTrip) {
  EXPECT_EQ(CsvNumber(0.1), "0.1");
  EXPECT_EQ(std::stod(CsvNumber(1.0 / 3.0)), 1.0 / 3.0);
  EXPECT_EQ(CsvNumber(std::nan("")), "");
}

}  // namespace
}  // namespace bead
