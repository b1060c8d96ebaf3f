// The C interface (bead/bead.h, libbead.so): the same numbers as the C++
// classes it wraps, clear errors instead of exceptions, and the examples
// (a C program, a Python ctypes script) agreeing with `bead measure`.
#include "bead/bead.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "libbead/flow/flow.h"
#include "libbead/flow/streaming_flow.h"
#include "libbead/io/csv_reader.h"
#include "libbead/io/profiles_csv.h"
#include "libbead/profile/profile_processor.h"
#include "libbead/sim/rig_simulator.h"
#include "tests/support/run_cli.h"

namespace bead {
namespace {

sim::SimulatedRun SmallRun() {
  sim::SimConfig c;
  c.seed = 11;
  c.duration_s = 4;
  c.sensor.points = 200;
  return sim::Simulate(c);
}

TEST(CInterface, BadArgumentsAreErrorsWithAMessage) {
  const double left[2] = {-24, -12}, inverted[2] = {12, -12}, right[2] = {12, 24};
  EXPECT_EQ(bead_processor_create(inverted, right), nullptr);
  EXPECT_NE(std::string(bead_last_error()).find("left_mm must be two finite x"), std::string::npos)
      << bead_last_error();
  EXPECT_EQ(bead_processor_create(right, left), nullptr);  // the areas swapped
  EXPECT_NE(std::string(bead_last_error()).find("must end before"), std::string::npos) << bead_last_error();
  bead_options unset{};  // size not filled in
  EXPECT_EQ(bead_processor_create_with(left, right, &unset), nullptr);
  EXPECT_NE(std::string(bead_last_error()).find("_init"), std::string::npos) << bead_last_error();
  bead_processor* p = bead_processor_create(left, right);
  ASSERT_NE(p, nullptr);
  bead_geometry g;
  EXPECT_EQ(bead_processor_measure(p, nullptr, nullptr, 5, &g), -1);
  EXPECT_EQ(bead_processor_measure(nullptr, nullptr, nullptr, 0, &g), -1);
  // An empty profile is measured: no points, a status that says so.
  EXPECT_EQ(bead_processor_measure(p, nullptr, nullptr, 0, &g), 0);
  EXPECT_EQ(g.valid, 0);
  EXPECT_STREQ(bead_status_name(g.status), "too_few_points");
  bead_processor_destroy(p);
  bead_rig rig;
  bead_rig_init(&rig);  // counts and diameter left 0
  EXPECT_EQ(bead_flow_create(&rig, nullptr, 500.0), nullptr);
  EXPECT_NE(std::string(bead_last_error()).find("counts_per_rev"), std::string::npos) << bead_last_error();
  // The rig file's rules (core/rig.h IsValid), named by the rig file's key.
  rig.counts_per_rev = 20480.0;
  rig.wheel_diameter_mm = 254.762;
  rig.encoder_bits = 4;
  EXPECT_EQ(bead_flow_create(&rig, nullptr, 500.0), nullptr);
  EXPECT_NE(std::string(bead_last_error()).find("encoder.bits"), std::string::npos) << bead_last_error();
  EXPECT_STREQ(bead_status_name(99), "unknown");
  EXPECT_STREQ(bead_version(), BEAD_VERSION_TEXT);
}

// Profile by profile, the processor's numbers exactly; the flow's samples
// exactly StreamingFlow's.
TEST(CInterface, SameNumbersAsTheClassesItWraps) {
  const sim::SimulatedRun m = SmallRun();
  const ProfileBlock& b = m.run.profiles;
  const Rig& rig = m.rig_file;
  const double left[2] = {rig.reference_left.x_min_mm, rig.reference_left.x_max_mm};
  const double right[2] = {rig.reference_right.x_min_mm, rig.reference_right.x_max_mm};
  bead_processor* p = bead_processor_create(left, right);
  ASSERT_NE(p, nullptr) << bead_last_error();
  ProfileProcessor cpp(rig.reference_left, rig.reference_right);

  bead_rig crig;
  bead_rig_init(&crig);
  crig.counts_per_rev = rig.encoder.counts_per_rev;
  crig.encoder_bits = rig.encoder.bits;
  crig.encoder_direction = rig.encoder.direction;
  crig.wheel_diameter_mm = rig.wheel_diameter_mm;
  crig.offset_counts = rig.offset_counts;
  const double rate = 500.0;
  bead_flow* flow = bead_flow_create(&crig, nullptr, rate);
  ASSERT_NE(flow, nullptr) << bead_last_error();
  StreamingFlow stream(rig, FlowOptions{}, rate);
  const AcquisitionLog& log = *m.run.log;
  std::size_t li = 0;
  int valid = 0, samples = 0;
  auto drain = [&]() {
    bead_flow_sample cs;
    FlowSample s;
    while (bead_flow_pop(flow, &cs) == 1) {
      ASSERT_TRUE(stream.Pop(s));
      EXPECT_EQ(cs.profile, s.profile);
      EXPECT_EQ(cs.valid, s.valid ? 1 : 0);
      if (s.valid) {
        EXPECT_EQ(cs.flow_mm3_s, s.flow_mm3_s) << s.profile;
      }
      ++samples;
    }
    EXPECT_FALSE(stream.Pop(s));
  };
  for (std::size_t k = 0; k < b.size(); ++k) {
    while (li < log.size() && log.t_s[li] <= b.t_s[k]) {
      ASSERT_EQ(bead_flow_push_log(flow, log.t_s[li], log.encoder[li], log.screw_rpm[li]), 0);
      stream.PushLog(log.t_s[li], log.encoder[li], log.screw_rpm[li]);
      ++li;
    }
    const ProfileView v = b.view(k);
    bead_geometry g;
    ASSERT_EQ(bead_processor_measure(p, v.x_mm.data(), v.z_mm.data(), v.x_mm.size(), &g), 0);
    const BeadGeometry& e = cpp.Process(v);
    EXPECT_EQ(g.status, static_cast<int32_t>(e.status)) << k;
    if (e.valid()) {
      ++valid;
      EXPECT_EQ(g.area_mm2, e.area_mm2) << k;
      EXPECT_EQ(g.width_mm, e.width_mm) << k;
      EXPECT_EQ(g.height_mm, e.height_mm) << k;
      EXPECT_EQ(g.center_x_mm, e.center_x_mm) << k;
    }
    ASSERT_EQ(bead_flow_push_profile(flow, v.t_s, v.encoder, &g), 0);
    stream.PushProfile(v.t_s, v.encoder, e);
    drain();
  }
  ASSERT_EQ(bead_flow_finish(flow), 0);
  stream.Finish();
  drain();
  EXPECT_GT(valid, 300);
  EXPECT_EQ(samples, static_cast<int>(b.size()));
  bead_flow_destroy(flow);
  bead_processor_destroy(p);
}

// profile -> (area, width, height, centre, valid) from a CSV with that
// header's columns.
struct Row {
  double area, width, height, centre;
  int valid;
};
std::vector<Row> ReadRows(const std::string& path) {
  CsvReader csv(path);
  const auto header = csv.Header({"profile"}, "output");
  auto col = [&](const std::string& name) {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return i;
    ADD_FAILURE() << path << " lacks " << name;
    return std::size_t{0};
  };
  const std::size_t a = col("area_mm2"), w = col("width_mm"), h = col("height_mm"), c = col("center_x_mm"),
                    v = col("valid");
  std::vector<Row> rows;
  while (csv.Next()) {
    auto number = [&](std::size_t i) {
      const std::string f(csv.Field(i));
      return f.empty() || f == "nan" ? NAN : std::stod(f);
    };
    rows.push_back({number(a), number(w), number(h), number(c), static_cast<int>(number(v))});
  }
  return rows;
}

void ExpectSameRows(const std::vector<Row>& got, const std::vector<Row>& want, const std::string& who) {
  ASSERT_EQ(got.size(), want.size()) << who;
  int valid = 0;
  for (std::size_t k = 0; k < want.size(); ++k) {
    EXPECT_EQ(got[k].valid, want[k].valid) << who << " profile " << k;
    if (!want[k].valid) continue;
    ++valid;
    // Printed with 9 significant digits against the CSV's round trip.
    for (auto [g, w] : {std::pair{got[k].area, want[k].area}, std::pair{got[k].width, want[k].width},
                        std::pair{got[k].height, want[k].height}, std::pair{got[k].centre, want[k].centre}})
      EXPECT_NEAR(g, w, 1e-8 * std::max(1.0, std::abs(w))) << who << " profile " << k;
  }
  EXPECT_GT(valid, 300) << who;
}

TEST(CInterface, ExamplesAgreeWithBeadMeasure) {
  test::TempDir dir;
  const sim::SimulatedRun m = SmallRun();
  WriteProfilesCsv(dir / "profiles.csv", m.run.profiles);
  const Rig& rig = m.rig_file;
  test::WriteText(dir / "rig.yaml",
                  "encoder: {counts_per_rev: 4096, bits: 32, direction: 1}\n"
                  "wheel: {diameter_mm: 254.762}\noffset: {counts: 3000}\nsensor: {reference_areas_mm: [[" +
                      std::to_string(rig.reference_left.x_min_mm) + ", " + std::to_string(rig.reference_left.x_max_mm) +
                      "], [" + std::to_string(rig.reference_right.x_min_mm) + ", " +
                      std::to_string(rig.reference_right.x_max_mm) + "]]}\n");
  auto [st, out] = test::RunCli(dir, "measure --occlusion none --rig " + (dir / "rig.yaml") + " " +
                                         (dir / "profiles.csv") + " -o " + (dir / "geometry.csv"));
  ASSERT_EQ(st, 0) << out;
  const auto want = ReadRows(dir / "geometry.csv");
  std::ostringstream areas;
  areas << rig.reference_left.x_min_mm << ' ' << rig.reference_left.x_max_mm << ' ' << rig.reference_right.x_min_mm
        << ' ' << rig.reference_right.x_max_mm << ' ' << (dir / "profiles.csv");
  const std::string c_cmd = std::string(BEAD_C_EXAMPLE) + " " + areas.str() + " > " + (dir / "c.csv");
  ASSERT_EQ(std::system(c_cmd.c_str()), 0) << c_cmd;
  ExpectSameRows(ReadRows(dir / "c.csv"), want, "C example");
#ifndef BEAD_SANITIZED  // python would need the sanitizer's runtime preloaded
  const std::string py_cmd = std::string("BEAD_LIBRARY=") + BEAD_C_LIBRARY + " python3 " + BEAD_SOURCE_DIR +
                             "/examples/python/measure_profiles.py " + areas.str() + " > " + (dir / "py.csv");
  ASSERT_EQ(std::system(py_cmd.c_str()), 0) << py_cmd;
  ExpectSameRows(ReadRows(dir / "py.csv"), want, "Python ctypes example");
#endif
}

}  // namespace
}  // namespace bead
