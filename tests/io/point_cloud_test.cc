// Point clouds out and in (PLY, PCD through PCL). A twin run exported in
// wheel coordinates: s follows the surface speed to an encoder count, the
// bare surface sits at height 0 to its noise, and the run read back from
// the cloud measures the same as the run itself, bit for bit. Clouds made
// by other tools (ASCII PLY with the lines shuffled, an organized PCD)
// come in ordered by the field the user names; bad ones are named.
#include "libbead/io/point_cloud.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "libbead/io/rig_yaml.h"
#include "tests/support/expect_rejected.h"
#include "tests/support/run_cli.h"
#include "tests/support/error_stats.h"

namespace bead {
namespace {

// Rows of a geometry CSV by profile time, the columns as text (so that
// "the same" means the same digits).
std::map<std::string, std::map<std::string, std::string>> GeometryRows(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::stringstream hs(line);
  for (std::string f; std::getline(hs, f, ',');) header.push_back(f);
  std::map<std::string, std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::map<std::string, std::string> row;
    for (const std::string& h : header) std::getline(ss, row[h], ',');
    rows[row["t_s"]] = row;
  }
  return rows;
}

using test::Median;

TEST(PointCloud, TwinRunRoundTripsThroughPlyAndPcd) {
  test::TempDir dir;
  // Constant wheel: 200 mm/s surface speed (the simulator's default).
  test::WriteText(dir / "sim.yaml", "seed: 7\nduration_s: 3\nsensor: {points: 300}\npins: {scans: 0}\n");
  auto [sim, sim_out] = test::RunCli(dir, "simulate " + (dir / "sim.yaml") + " -o " + (dir / "twin"));
  ASSERT_EQ(sim, 0) << sim_out;
  const std::string rig_path = dir / "twin/rig.yaml", run = dir / "twin/run.h5";
  const Rig rig = ReadRig(rig_path);
  auto [g0, g0_out] =
      test::RunCli(dir, "measure --occlusion none --rig " + rig_path + " " + run + " -o " + (dir / "g0.csv"));
  ASSERT_EQ(g0, 0) << g0_out;
  const auto original = GeometryRows(dir / "g0.csv");

  for (const char* ext : {"ply", "pcd"}) {
    SCOPED_TRACE(ext);
    const std::string cloud_path = dir / (std::string("run.") + ext);
    auto [ex, ex_out] = test::RunCli(dir, "export --rig " + rig_path + " " + run + " -o " + cloud_path);
    ASSERT_EQ(ex, 0) << ex_out;

    // Wheel coordinates, read as another tool would (z is the height).
    const ImportedRun as_height =
        ReadPointCloud(cloud_path, Columns("profile", "t_s", "x", "z", "encoder", 1.0, false));
    const ImportedRun as_s = ReadPointCloud(cloud_path, Columns("profile", "t_s", "x", "y", "", 1.0, false));
    const ProfileBlock& h = as_height.run.profiles;
    const ProfileBlock& s = as_s.run.profiles;
    ASSERT_EQ(h.size(), s.size());
    ASSERT_GT(h.size(), 590u);  // 3 s at 200 Hz; only profiles without a reference line are left out
    // s = v (t - t0) to within one encoder count (pi D / counts per rev)
    // and float rounding of s.
    const double count_mm = rig.MmPerCount();
    std::vector<double> bare;
    for (std::size_t i = 0; i < s.size(); ++i) {
      const ProfileView vs = s.view(i), vh = h.view(i);
      for (std::size_t k = 0; k < vs.z_mm.size(); ++k) {
        if (std::isnan(vs.z_mm[k])) continue;
        ASSERT_NEAR(vs.z_mm[k], 200.0 * (s.t_s[i] - s.t_s[0]), count_mm + 1e-6 * 600.0) << "profile " << i;
        if (rig.reference_left.Contains(vh.x_mm[k]) || rig.reference_right.Contains(vh.x_mm[k]))
          bare.push_back(std::fabs(vh.z_mm[k]));
      }
    }
    // The bare surface at height 0: median |z| of Gaussian noise is 0.674
    // sigma; the reference lines' RMS is that sigma.
    std::vector<double> rms;
    for (const auto& [t, row] : original)
      if (!row.at("reference_rms_mm").empty()) rms.push_back(std::stod(row.at("reference_rms_mm")));
    EXPECT_LT(Median(bare), 0.674 * Median(rms) * 1.2);

    // The run back from the cloud, with the sensor's own z: every profile
    // with a reference line measures the same, digit for digit.
    auto [im, im_out] = test::RunCli(dir, std::string("import ") + cloud_path + " -o " + (dir / "back.h5") +
                                              " --profile-column profile --time-column t_s --x-column x"
                                              " --z-column z_sensor --encoder-column encoder");
    ASSERT_EQ(im, 0) << im_out;
    auto [g1, g1_out] = test::RunCli(
        dir, "measure --occlusion none --rig " + rig_path + " " + (dir / "back.h5") + " -o " + (dir / "g1.csv"));
    ASSERT_EQ(g1, 0) << g1_out;
    const auto back = GeometryRows(dir / "g1.csv");
    std::size_t compared = 0, left_out = 0;
    for (const auto& [t, row] : original) {
      const auto it = back.find(t);
      if (it == back.end()) {
        // Left out: no reference line (too few points in an area, or at all).
        EXPECT_TRUE(row.at("status") == "no_reference" || row.at("status") == "too_few_points") << "t " << t;
        ++left_out;
        continue;
      }
      ++compared;
      for (const char* key : {"encoder", "status", "area_mm2", "width_mm", "height_mm", "center_x_mm",
                              "reference_rms_mm", "area_sigma_mm2"})
        EXPECT_EQ(it->second.at(key), row.at(key)) << key << " at t " << t;
      // Dropouts (NaN) are not points of a cloud: fewer may be counted.
      EXPECT_LE(std::stoi(it->second.at("dropped_points")), std::stoi(row.at("dropped_points")));
    }
    EXPECT_EQ(compared + left_out, original.size());
    EXPECT_EQ(compared, h.size());
  }
}

TEST(PointCloud, ForeignAsciiPlyIsOrderedByTheNamedField) {
  test::TempDir dir;
  // As CloudCompare saves scalar fields; the scan lines out of order, z a
  // distance from the sensor, time in ms.
  test::WriteText(dir / "scan.ply",
                  "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\n"
                  "property float scalar_Line\nproperty double scalar_Time\nend_header\n"
                  "0 0 -101 2 20\n1 0 -102 2 20\n"
                  "0 0 -100 0 0\n1 0 -103 0 0\n"
                  "0 0 -104 1 10\n1 0 -105 1 10\n");
  const ImportedRun r =
      ReadPointCloud(dir / "scan.ply", Columns("scalar_Line", "scalar_Time", "x", "z", "", 1e-3, true));
  const ProfileBlock& b = r.run.profiles;
  ASSERT_EQ(b.size(), 3u);
  EXPECT_EQ(r.rows, 6u);
  EXPECT_TRUE(b.shared_x);
  EXPECT_TRUE(EncoderAbsent(r.run));
  const double t[] = {0.0, 0.010, 0.020};
  const float z[3][2] = {{100, 103}, {104, 105}, {101, 102}};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_DOUBLE_EQ(b.t_s[i], t[i]);
    for (std::size_t k = 0; k < 2; ++k) EXPECT_EQ(b.view(i).z_mm[k], z[i][k]) << i << "," << k;
  }
}

TEST(PointCloud, OrganizedPcdGivesAProfilePerRow) {
  test::TempDir dir;
  test::WriteText(dir / "grid.pcd",
                  "VERSION .7\nFIELDS x z t\nSIZE 4 4 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 2\n"
                  "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 6\nDATA ascii\n"
                  "-1 0 0.5\n0 2 0.5\n1 nan 0.5\n-1 0 0.6\n0 3 0.6\n1 0 0.6\n");
  const ImportedRun r = ReadPointCloud(dir / "grid.pcd", Columns("", "t", "x", "z", "", 1.0, false));
  const ProfileBlock& b = r.run.profiles;
  ASSERT_EQ(b.size(), 2u);
  EXPECT_DOUBLE_EQ(b.t_s[1], 0.6);
  EXPECT_EQ(b.view(0).z_mm[1], 2.0f);
  EXPECT_TRUE(std::isnan(b.view(0).z_mm[2]));  // a dropout stays one
  EXPECT_EQ(b.view(1).z_mm[1], 3.0f);
}

TEST(PointCloud, BadCloudsAreNamed) {
  test::TempDir dir;
  const std::string ply_head =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float z\n"
      "property float line\nproperty float t\nend_header\n";
  test::WriteText(dir / "ok.ply", ply_head + "0 1 0 0\n1 1 1 1\n");
  test::ExpectRejected(dir / "ok.ply", "no field 'scan' for the scan line (the cloud has: x, z, line, t)",
                       [&] { ReadPointCloud(dir / "ok.ply", Columns("scan", "t", "x", "z", "", 1.0, false)); });
  test::ExpectRejected(dir / "ok.ply", "name the field that numbers the scan lines",
                       [&] { ReadPointCloud(dir / "ok.ply", Columns("", "t", "x", "z", "", 1.0, false)); });
  test::WriteText(dir / "nan.ply", ply_head + "0 1 nan 0\n1 1 1 1\n");
  test::ExpectRejected(dir / "nan.ply", "point 0: the scan line field 'line' is not finite",
                       [&] { ReadPointCloud(dir / "nan.ply", Columns("line", "t", "x", "z", "", 1.0, false)); });
  // Lines ordered by a field that runs against time.
  test::WriteText(dir / "back.ply", ply_head + "0 1 0 5\n1 1 1 1\n");
  test::ExpectRejected(dir / "back.ply", "t_s",
                       [&] { ReadPointCloud(dir / "back.ply", Columns("line", "t", "x", "z", "", 1.0, false)); });
  test::WriteText(dir / "text.ply", "this is no cloud\n");
  test::ExpectRejected(dir / "text.ply", "not a PLY file PCL can read",
                       [&] { ReadPointCloud(dir / "text.ply", Columns("line", "t", "x", "z", "", 1.0, false)); });
  test::WriteText(dir / "cut.pcd", "VERSION .7\nFIELDS x z t\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 4\n");
  test::ExpectRejected(dir / "cut.pcd", "not a PCD file PCL can read",
                       [&] { ReadPointCloud(dir / "cut.pcd", Columns("", "t", "x", "z", "", 1.0, false)); });
  test::ExpectRejected(dir / "out.xyz", "a point cloud is written as .ply or .pcd",
                       [&] { WritePointCloud(dir / "out.xyz", WheelCloud{}); });
}

}  // namespace
}  // namespace bead
