#include "libbead/series/encoder.h"

#include <gtest/gtest.h>

#include <cmath>

namespace bead {
namespace {

std::vector<int64_t> Raw(const std::vector<double>& counts, const EncoderSpec& spec) {
  std::vector<int64_t> raw;
  for (double c : counts) raw.push_back(RawFromCounts(std::floor(c), spec));
  return raw;
}

// A 12-bit counter counting down (direction -1) over several wraps unwraps
// to the surface position, growing.
TEST(Encoder, UnwrapsWrapAndDirection) {
  const EncoderSpec spec{20480, 12, -1};
  std::vector<double> truth;
  for (int i = 0; i < 2000; ++i) truth.push_back(1000.0 + 13.37 * i);  // 26,700 counts: 6 wraps
  const EncoderTrack t = UnwrapEncoder(Raw(truth, spec), spec);
  for (std::size_t i = 0; i < truth.size(); ++i)
    EXPECT_NEAR(t.counts[i] - t.counts[0], std::floor(truth[i]) - std::floor(truth[0]), 1e-9);
  EXPECT_EQ(t.missed_reads + t.glitches, 0);
  // The streaming unwrapper agrees.
  EncoderUnwrapper stream(spec);
  const auto raw = Raw(truth, spec);
  for (std::size_t i = 0; i < raw.size(); ++i) EXPECT_DOUBLE_EQ(stream.Push(raw[i]), t.counts[i]);
}

// Missed reads (a repeated value) and glitches (one wild value) are
// repaired by interpolation in time, and counted.
TEST(Encoder, RepairsMissedReadsAndGlitches) {
  const EncoderSpec spec{20480, 32, 1};
  std::vector<double> truth, t;
  for (int i = 0; i < 500; ++i) {
    t.push_back(0.002 * i);
    truth.push_back(5e5 + 10.0 * i);
  }
  auto raw = Raw(truth, spec);
  raw[100] = raw[99];          // missed read
  raw[300] = raw[300] + 7777;  // glitch
  raw[301] = raw[301];         // (next read fine)
  const EncoderTrack track = UnwrapEncoder(raw, spec, t);
  EXPECT_EQ(track.missed_reads, 1);
  EXPECT_EQ(track.glitches, 1);
  EXPECT_NEAR(track.counts[100], truth[100], 1.0);
  EXPECT_NEAR(track.counts[300], truth[300], 1.0);
  EXPECT_NEAR(track.counts[499], truth[499], 1e-9);
}

// One revolution is 2 pi and one circumference, pi D.
TEST(Encoder, CountsToAngleAndSurface) {
  Rig rig;
  rig.encoder = {20480, 32, 1};
  rig.wheel_diameter_mm = 254.762;
  EXPECT_NEAR(CountsToAngleRad(20480, rig.encoder), 2 * M_PI, 1e-12);
  EXPECT_NEAR(CountsToMm(20480, rig), M_PI * 254.762, 1e-9);
}

TEST(Encoder, UnwrapNearAndRawRoundTrip) {
  const EncoderSpec spec{4096, 16, 1};
  EXPECT_DOUBLE_EQ(UnwrapNear(10, spec, 65536.0 * 3 + 5), 65536.0 * 3 + 10);
  EXPECT_DOUBLE_EQ(UnwrapNear(65530, spec, 65536.0 * 3 + 5), 65536.0 * 3 - 6);
  EXPECT_EQ(RawFromCounts(65536.0 * 3 - 6, spec), 65530);
  const EncoderSpec down{4096, 16, -1};
  EXPECT_EQ(RawFromCounts(UnwrapNear(1234, down, -70000), down), 1234);
}

}  // namespace
}  // namespace bead
