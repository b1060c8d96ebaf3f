// A part scan (format 1.1) read and written as the spec says, and its rig
// file's part: section; each wrong file named with its place.
#include <gtest/gtest.h>

#include <string>

#include "libbead/core/error.h"
#include "libbead/io/hdf5_file.h"
#include "libbead/io/profile_stream.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/io/run_archive.h"
#include "libbead/sim/part_twin.h"
#include "tests/support/expect_rejected.h"
#include "tests/support/temp_dir.h"

namespace bead {
namespace {

sim::PartTwinConfig SmallWall() {
  sim::PartTwinConfig c;
  c.layers = 3;
  c.length_mm = 10.0;
  return c;
}

using test::ErrorOf;

TEST(PartScan, WrittenAndReadBackWithItsPlacesAndItsLog) {
  test::TempDir dir;
  const sim::PartTwin twin = sim::SimulatePartWall(SmallWall());
  const std::string path = dir / "part.h5";
  WriteRunArchive(path, twin.scan);
  ASSERT_TRUE(IsPartScan(path));
  const RunArchive back = ReadPartScan(path);
  ASSERT_TRUE(back.part.has_value());
  EXPECT_EQ(back.part->layer, twin.scan.part->layer);
  EXPECT_EQ(back.part->path_mm, twin.scan.part->path_mm);
  EXPECT_EQ(back.part->frame_z_mm, twin.scan.part->frame_z_mm);
  EXPECT_EQ(back.profiles.z_mm, twin.scan.profiles.z_mm);
  EXPECT_TRUE(EncoderAbsent(back));
  ASSERT_TRUE(back.log.has_value());
  EXPECT_TRUE(back.log->encoder.empty());
  EXPECT_EQ(back.log->layer, twin.scan.log->layer);
  EXPECT_EQ(back.log->path_mm, twin.scan.log->path_mm);
  EXPECT_EQ(back.log->head_speed_mm_s, twin.scan.log->head_speed_mm_s);
  EXPECT_TRUE(back.log->channels.empty()) << "the part's motion is not a recorded channel";
  // As the spec says: no encoder datasets, kind = "part" at the root.
  const h5::File f = h5::File::OpenRead(path);
  EXPECT_FALSE(f.Exists("/profiles/encoder"));
  EXPECT_FALSE(f.Exists("/log/encoder"));
  EXPECT_EQ(f.ReadStringAttributes("/").at("kind"), "part");
  // Streamed: the same profiles, encoder 0.
  WorkerPool pool(2);
  ProfileStream stream(path, pool);
  ProfileBlock block;
  stream.Read(0, stream.size(), block);
  EXPECT_EQ(block.z_mm, twin.scan.profiles.z_mm);
  EXPECT_EQ(block.encoder, std::vector<int64_t>(stream.size(), 0));
}

TEST(PartScan, TheWheelsReadersAndThePartsReaderNameTheOthersFile) {
  test::TempDir dir;
  const std::string part = dir / "part.h5", run = dir / "run.h5";
  const sim::PartTwin twin = sim::SimulatePartWall(SmallWall());
  WriteRunArchive(part, twin.scan);
  RunArchive wheel = twin.scan;
  wheel.part.reset();
  wheel.log.reset();
  wheel.attributes.clear();
  WriteRunArchive(run, wheel);
  EXPECT_NE(ErrorOf([&] { ReadRunArchive(part); }).find("is a part scan"), std::string::npos);
  EXPECT_NE(ErrorOf([&] { ReadPartScan(run); }).find("is not a part scan"), std::string::npos);
  EXPECT_FALSE(IsPartScan(run));
}

TEST(PartScan, APlaceOutOfOrderOrMissingIsNamed) {
  test::TempDir dir;
  sim::PartTwin twin = sim::SimulatePartWall(SmallWall());
  const std::string path = dir / "part.h5";
  // A layer that falls: the profiles of a layer lie together.
  RunArchive bad = twin.scan;
  bad.part->layer[5] = 2;
  EXPECT_NE(ErrorOf([&] { WriteRunArchive(path, bad); }).find("/profiles/layer[6]"), std::string::npos);
  bad = twin.scan;
  bad.part->path_mm[3] = std::nan("");
  EXPECT_NE(ErrorOf([&] { WriteRunArchive(path, bad); }).find("/profiles/path_mm[3]"), std::string::npos);
  // A dataset missing from a file made elsewhere.
  WriteRunArchive(path, twin.scan);
  {
    h5::File f = h5::File::OpenReadWrite(path);
    ASSERT_EQ(H5Ldelete(f.id(), "/profiles/frame_z_mm", H5P_DEFAULT), 0);
  }
  const std::string e = ErrorOf([&] { ReadPartScan(path); });
  EXPECT_NE(e.find(path), std::string::npos) << e;
  EXPECT_NE(e.find("/profiles/frame_z_mm"), std::string::npos) << e;
}

TEST(PartRig, APartRigNeedsNoWheelAndItsBedIsChecked) {
  const std::string areas = "sensor:\n  reference_areas_mm: [[-20, -15], [15, 20]]\n";
  const RigFile pipe = ParseRig("part:\n  bed: cylinder\n  bed_radius_mm: 60\n" + areas, "r.yaml", true, false);
  EXPECT_FALSE(pipe.rig.has_wheel);
  ASSERT_TRUE(pipe.rig.part.has_value());
  EXPECT_EQ(pipe.rig.part->shape, PartBed::Shape::kCylinder);
  EXPECT_EQ(pipe.rig.part->radius_mm, 60.0);
  const RigFile flat = ParseRig("part: {bed: flat}\n" + areas, "r.yaml", true, false);
  EXPECT_EQ(flat.rig.part->shape, PartBed::Shape::kFlat);
  // What needs the wheel says what is missing.
  EXPECT_NE(ErrorOf([&] { ParseRig("part: {bed: flat}\n" + areas, "r.yaml"); }).find("encoder: missing key"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] { ParseRig("part: {bed: sphere}\n" + areas, "r.yaml", true, false); }).find("part.bed"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] {
              ParseRig("part: {bed: flat, bed_radius_mm: 5}\n" + areas, "r.yaml", true, false);
            }).find("is for a cylinder bed"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] {
              ParseRig("part: {bed: cylinder, bed_radius_mm: -5}\n" + areas, "r.yaml", true, false);
            }).find("positive radius"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] { ParseRig("part: {bed: flat}\n", "r.yaml", true, false); }).find("sensor"), std::string::npos);
}

TEST(PartRig, WrittenBackItKeepsThePartAndWritesNoWheel) {
  test::TempDir dir;
  const std::string areas = "sensor:\n  reference_areas_mm: [[-20, -15], [15, 20]]\n";
  RigFile rig = ParseRig("name: pipe\npart:\n  bed: cylinder\n  bed_radius_mm: 60\n" + areas, "r.yaml", true, false);
  WriteRigFile(dir / "rig.yaml", rig);
  const std::string text = test::ReadText(dir / "rig.yaml");
  EXPECT_EQ(text.find("encoder"), std::string::npos) << text;
  const RigFile back = ReadPartRigFile(dir / "rig.yaml");
  EXPECT_EQ(back.rig.part->radius_mm, 60.0);
  EXPECT_FALSE(back.rig.has_wheel);
}

}  // namespace
}  // namespace bead
