// One rule set for a rig (core/rig.h IsValid), and every source of a rig
// held to it: the rig file, the simulator's config (the C interface's
// test, capi_test.cc, holds bead_flow_create to the same rules).
#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "libbead/core/error.h"
#include "libbead/core/rig.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/sim/sim_config.h"

namespace bead {
namespace {

Rig Good() {
  Rig r;
  r.encoder = {20480.0, 32, 1};
  r.wheel_diameter_mm = 254.762;
  r.offset_counts = 3071.5;
  r.reference_left = {-24.0, -12.0};
  r.reference_right = {12.0, 24.0};
  return r;
}

TEST(RigRules, EachRuleNamesItsKey) {
  std::string key, error;
  ASSERT_TRUE(IsValid(Good(), true, &key, &error)) << key << " " << error;
  const struct {
    const char* key;
    std::function<void(Rig&)> breaks;
  } cases[] = {
      {"encoder.counts_per_rev", [](Rig& r) { r.encoder.counts_per_rev = 0; }},
      {"encoder.counts_per_rev", [](Rig& r) { r.encoder.counts_per_rev = NAN; }},
      {"encoder.bits", [](Rig& r) { r.encoder.bits = 4; }},
      {"encoder.bits", [](Rig& r) { r.encoder.bits = 65; }},
      {"encoder.direction", [](Rig& r) { r.encoder.direction = 0; }},
      {"wheel.diameter_mm", [](Rig& r) { r.wheel_diameter_mm = -1; }},
      {"wheel.eccentricity_mm", [](Rig& r) { r.wheel_eccentricity_mm = 30.0; }},
      {"wheel.eccentricity_mm", [](Rig& r) { r.wheel_eccentricity_mm = -0.1; }},
      {"wheel.eccentricity_phase_deg", [](Rig& r) { r.wheel_eccentricity_phase_deg = 400; }},
      {"offset.counts", [](Rig& r) { r.offset_counts = INFINITY; }},
      {"sensor.reference_areas_mm[0]",
       [](Rig& r) {
         r.reference_left = {-12.0, -24.0};
       }},
      {"sensor.reference_areas_mm",
       [](Rig& r) {
         r.reference_right = {-13.0, 24.0};
       }},
      {"sensor.laser_origin_mm",
       [](Rig& r) {
         r.laser_origin = LaserOrigin{NAN, 95.0};
       }},
  };
  for (const auto& c : cases) {
    Rig r = Good();
    c.breaks(r);
    EXPECT_FALSE(IsValid(r, true, &key, &error)) << c.key;
    EXPECT_EQ(key, c.key) << error;
    EXPECT_FALSE(error.empty());
  }
  // Reference areas are the measurement's business: a flow needs none.
  Rig r = Good();
  r.reference_right = {-13.0, 24.0};
  EXPECT_TRUE(IsValid(r, false, &key, &error));
}

TEST(RigRules, TheRigFileAndTheSimulatorConfigRefuseAlike) {
  const std::string rig_text =
      "encoder: {counts_per_rev: 20480, bits: 4, direction: 1}\nwheel: {diameter_mm: 254.762}\n"
      "offset: {counts: 3071.5}\nsensor: {reference_areas_mm: [[-24, -12], [12, 24]]}\n";
  try {
    ParseRig(rig_text, "rig.yaml");
    ADD_FAILURE() << "bits 4 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("encoder.bits"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("line 1"), std::string::npos) << e.what();
  }
  try {
    sim::ParseSimConfig("rig: {bits: 4}\n", "sim.yaml");
    ADD_FAILURE() << "bits 4 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("encoder.bits"), std::string::npos) << e.what();
  }
  // The simulator refused no overlapping areas before the one rule set.
  EXPECT_THROW(sim::ParseSimConfig("rig: {reference_areas_mm: [[-24, 2], [-2, 24]]}\n", "sim.yaml"), Error);
}

}  // namespace
}  // namespace bead
