// A part scan exported as a point cloud lies in the bed frame, its layers
// stacked at their heights, each point with its layer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "libbead/io/point_cloud.h"
#include "libbead/io/run_archive.h"
#include "libbead/part/part_cloud.h"
#include "libbead/sim/part_twin.h"
#include "tests/support/temp_dir.h"

namespace bead {
namespace {

TEST(PartCloud, ThePartComesBackInTheBedFrameWithItsLayers) {
  test::TempDir dir;
  sim::PartTwinConfig config;
  config.layers = 3;
  config.length_mm = 4.0;
  const sim::PartTwin twin = sim::SimulatePartWall(config);
  const RunArchive& scan = twin.scan;
  WritePointCloud(dir / "part.ply", part::BuildPartCloud(scan.profiles, *scan.part));
  // Read back: x, z as the bed frame's, the layer as the "encoder" column.
  ImportColumns columns;
  columns.profile = "profile", columns.time = "t_s", columns.x = "x", columns.z = "z", columns.encoder = "layer";
  const ImportedRun back = ReadPointCloud(dir / "part.ply", columns);
  const ProfileBlock& b = back.run.profiles;
  ASSERT_EQ(b.size(), scan.profiles.size());
  for (std::size_t i = 0; i < b.size(); ++i) {
    EXPECT_EQ(b.encoder[i], scan.part->layer[i]) << i;
    const ProfileView got = b.view(i), sent = scan.profiles.view(i);
    ASSERT_EQ(got.z_mm.size(), sent.z_mm.size());
    for (std::size_t j = 0; j < got.z_mm.size(); j += 97) {
      EXPECT_FLOAT_EQ(got.x_mm[j], static_cast<float>(sent.x_mm[j] + scan.part->frame_x_mm[i]));
      EXPECT_FLOAT_EQ(got.z_mm[j], static_cast<float>(sent.z_mm[j] + scan.part->frame_z_mm[i]));
    }
  }
  // Stacked as printed: each layer's highest point stands above the one
  // below's by at least half the least crest gain the twin laid on it (a
  // layer's crest rises and falls along the path with the area's wave,
  // +-2 of 12 mm^2: half leaves room for that and nothing more).
  std::vector<double> top(config.layers, -1e9), least_gain(config.layers, 1e9);
  for (std::size_t i = 0; i < b.size(); ++i)
    for (float z : b.view(i).z_mm) top[b.encoder[i]] = std::max(top[b.encoder[i]], static_cast<double>(z));
  for (const auto& t : twin.truth) least_gain[t.layer] = std::min(least_gain[t.layer], t.height_mm);
  for (int k = 1; k < config.layers; ++k) EXPECT_GT(top[k] - top[k - 1], 0.5 * least_gain[k]) << "layer " << k;
}

}  // namespace
}  // namespace bead
