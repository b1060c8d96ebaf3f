// ProfileStream: windows of a run archive are the same values as the whole
// archive read at once, whatever the window and whatever the file's layout
// (our own shuffle+deflate chunks, inflated on worker threads; contiguous
// float64 as another tool may write it, converted by HDF5); damage is named.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <random>

#include "libbead/core/error.h"
#include "libbead/io/profile_stream.h"
#include "libbead/io/run_archive.h"
#include "tests/support/temp_dir.h"

namespace bead {
namespace {

// A block of n profiles of p points with per-profile x, NaN dropouts in x
// and z, values that do not compress to nothing.
ProfileBlock MakeBlock(std::size_t n, std::size_t p, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  ProfileBlock b;
  b.points = p;
  b.shared_x = false;
  for (std::size_t i = 0; i < n; ++i) {
    b.t_s.push_back(0.005 * static_cast<double>(i));
    b.encoder.push_back(static_cast<int64_t>(7 * i));
    for (std::size_t k = 0; k < p; ++k) {
      const bool dropout = rng() % 50 == 0;
      b.x_mm.push_back(dropout ? NAN : -25.0f + 50.0f * static_cast<float>(k) / static_cast<float>(p) + 0.01f * u(rng));
      b.z_mm.push_back(dropout ? NAN : 3.0f * u(rng));
    }
  }
  return b;
}

// dir/run.h5 holding `block` (libbead's own chunked, compressed layout).
std::string WriteArchive(const test::TempDir& dir, ProfileBlock block) {
  RunArchive run;
  run.profiles = std::move(block);
  const std::string path = dir / "run.h5";
  WriteRunArchive(path, run);
  return path;
}

// Profile j of `b` is profile `row` of `whole`: time, encoder, and the
// bytes of x and z (NaN payloads too).
::testing::AssertionResult SameProfile(const ProfileBlock& b, std::size_t j, const ProfileBlock& whole,
                                       std::size_t row) {
  const ProfileView v = b.view(j), w = whole.view(row);
  const std::size_t bytes = whole.points * sizeof(float);
  if (v.t_s != w.t_s || v.encoder != w.encoder || v.x_mm.size() != w.x_mm.size() ||
      std::memcmp(v.x_mm.data(), w.x_mm.data(), bytes) != 0 || std::memcmp(v.z_mm.data(), w.z_mm.data(), bytes) != 0)
    return ::testing::AssertionFailure() << "profile " << row << " differs";
  return ::testing::AssertionSuccess();
}

// Reads the archive in windows of `window` and checks each against `whole`.
void ExpectWindowsMatch(const std::string& path, const ProfileBlock& whole, std::size_t window, unsigned threads) {
  WorkerPool pool(threads);
  ProfileStream stream(path, pool);
  ASSERT_EQ(stream.size(), whole.size());
  ASSERT_EQ(stream.points(), whole.points);
  ProfileBlock b;
  for (std::size_t begin = 0; begin < whole.size(); begin += window) {
    const std::size_t count = std::min(window, whole.size() - begin);
    stream.Read(begin, count, b);
    ASSERT_EQ(b.size(), count);
    for (std::size_t i = 0; i < count; ++i) ASSERT_TRUE(SameProfile(b, i, whole, begin + i)) << "window " << window;
  }
}

TEST(ProfileStream, WindowsAreTheWholeArchiveWhateverTheirSize) {
  test::TempDir dir;
  const std::string path = WriteArchive(dir, MakeBlock(1000, 300, 1));  // chunks of 218 rows: windows cut through them
  const ProfileBlock whole = ReadRunArchive(path).profiles;
  for (std::size_t window : {1000u, 7u, 37u, 218u, 436u, 999u})
    for (unsigned threads : {1u, 3u}) ExpectWindowsMatch(path, whole, window, threads);
}

TEST(ProfileStream, ScatteredRowsAreTheWholeArchivesRows) {
  test::TempDir dir;
  const std::string path = WriteArchive(dir, MakeBlock(1000, 300, 5));
  const ProfileBlock whole = ReadRunArchive(path).profiles;
  const std::vector<std::size_t> rows = {0, 5, 217, 218, 219, 600, 999};  // within, across and at chunk ends
  WorkerPool pool(2);
  ProfileStream stream(path, pool);
  ProfileBlock b;
  stream.ReadRows(rows, b);
  ASSERT_EQ(b.size(), rows.size());
  for (std::size_t j = 0; j < rows.size(); ++j) EXPECT_TRUE(SameProfile(b, j, whole, rows[j]));
}

// Writes /profiles as another tool might: contiguous float64 z, shared x.
void WriteContiguousFloat64(const std::string& path, const ProfileBlock& b) {
  const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t g = H5Gcreate2(f, "/profiles", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  auto write = [&](const char* name, hid_t file_type, hid_t mem_type, const void* data, std::vector<hsize_t> dims) {
    const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
    const hid_t ds = H5Dcreate2(g, name, file_type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(ds, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
    H5Dclose(ds);
    H5Sclose(space);
  };
  const hsize_t n = b.size(), p = b.points;
  std::vector<double> z(b.z_mm.begin(), b.z_mm.end());
  write("t_s", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, b.t_s.data(), {n});
  write("encoder", H5T_STD_I32LE, H5T_NATIVE_INT64, b.encoder.data(), {n});
  write("x_mm", H5T_IEEE_F32BE, H5T_NATIVE_FLOAT, b.x_mm.data(), {p});
  write("z_mm", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, z.data(), {n, p});
  H5Gclose(g);
  H5Fclose(f);
}

TEST(ProfileStream, AnotherToolsLayoutIsConvertedByHdf5) {
  test::TempDir dir;
  ProfileBlock b = MakeBlock(500, 64, 2);
  b.shared_x = true;
  b.x_mm.resize(b.points);
  for (std::size_t k = 0; k < b.points; ++k) b.x_mm[k] = static_cast<float>(k);
  const std::string path = dir / "other.h5";
  WriteContiguousFloat64(path, b);
  ExpectWindowsMatch(path, ReadRunArchive(path).profiles, 33, 2);
}

TEST(ProfileStream, DamagedChunkIsNamedWithItsRow) {
  test::TempDir dir;
  const std::string path = WriteArchive(dir, MakeBlock(1000, 300, 3));
  // The file offset of the third chunk of z (rows 436 to 653).
  haddr_t address = 0;
  hsize_t size = 0;
  {
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const hid_t ds = H5Dopen2(f, "/profiles/z_mm", H5P_DEFAULT);
    hsize_t offset[2];
    unsigned mask = 0;
    const hid_t space = H5Dget_space(ds);
    ASSERT_GE(H5Dget_chunk_info(ds, space, 2, offset, &mask, &address, &size), 0);
    H5Sclose(space);
    ASSERT_EQ(offset[0], 436u);
    H5Dclose(ds);
    H5Fclose(f);
  }
  {
    std::fstream io(path, std::ios::in | std::ios::out | std::ios::binary);
    io.seekp(static_cast<std::streamoff>(address + size / 2));
    const std::string junk(64, '\x5a');
    io.write(junk.data(), static_cast<std::streamsize>(junk.size()));
  }
  WorkerPool pool(2);
  ProfileStream stream(path, pool);
  ProfileBlock b;
  stream.Read(0, 436, b);  // the chunks before it are whole
  try {
    stream.Read(436, 100, b);
    FAIL() << "a damaged chunk was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/profiles/z_mm chunk at row 436"), std::string::npos) << e.what();
  }
}

TEST(ProfileStream, TimeThatStepsBackAcrossWindowsIsNamedWithItsRow) {
  test::TempDir dir;
  const ProfileBlock block = MakeBlock(300, 16, 4);
  const std::string path = WriteArchive(dir, block);
  // t[200] = t[199]: written through HDF5 directly (our writer refuses it).
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hid_t ds = H5Dopen2(f, "/profiles/t_s", H5P_DEFAULT);
  std::vector<double> t = block.t_s;
  t[200] = t[199];
  H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, t.data());
  H5Dclose(ds);
  H5Fclose(f);
  WorkerPool pool(1);
  ProfileStream stream(path, pool);
  ProfileBlock b;
  stream.Read(0, 200, b);
  try {
    stream.Read(200, 100, b);
    FAIL() << "time that does not increase was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/profiles/t_s[200]: time does not increase"), std::string::npos) << e.what();
  }
}

TEST(ProfileStream, ProfilesInMemoryAreReadInPlaceAndCheckedAsAWindowIs) {
  const ProfileBlock block = MakeBlock(300, 16, 5);
  ProfileStream stream("scan.csv", block);
  const ProfileBlock* whole = stream.InMemory();
  ASSERT_NE(whole, nullptr);
  ProfileBlock window;
  stream.Read(0, 300, window);
  EXPECT_EQ(whole->t_s, window.t_s);
  EXPECT_EQ(std::memcmp(whole->z_mm.data(), window.z_mm.data(), window.z_mm.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(whole->x_mm.data(), window.x_mm.data(), window.x_mm.size() * sizeof(float)), 0);
  // An archive is read window by window.
  test::TempDir dir;
  WorkerPool pool(1);
  ProfileStream archive(WriteArchive(dir, block), pool);
  EXPECT_EQ(archive.InMemory(), nullptr);
  // Time that steps back is refused, named with its row.
  ProfileBlock bad = block;
  bad.t_s[200] = bad.t_s[199];
  ProfileStream refused("scan.csv", bad);
  try {
    refused.InMemory();
    FAIL() << "time that does not increase was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("scan.csv: /profiles/t_s[200]: time does not increase"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace bead
