// Files read where a fault inside a dependency cannot take the caller
// down (io/contained.h): a probe that crashes, asks for more memory than
// its budget or never finishes is reported as the file's corruption, by
// name, again and again; a probe's own error comes back as it was; a .mat
// whose header claims gigabytes costs the caller nothing; a run archive
// whose number types are not the format's is refused before libhdf5
// converts them.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <matio.h>
#include <signal.h>
#include <unistd.h>

#include <fstream>
#include <thread>

#include "libbead/core/error.h"
#include "libbead/io/contained.h"
#include "libbead/io/mat_file.h"
#include "libbead/io/run_archive.h"
#include "tests/support/run_cli.h"
#include "tests/support/temp_dir.h"

namespace bead {
namespace {

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// The process's peak address space (VmPeak), bytes.
std::size_t PeakBytes() {
  std::ifstream status("/proc/self/status");
  std::string key;
  std::size_t kb = 0;
  while (status >> key) {
    if (key == "VmPeak:") {
      status >> kb;
      return kb * 1024;
    }
    status.ignore(1 << 20, '\n');
  }
  return 0;
}

TEST(Contained, ACrashInsideTheLibraryIsTheFilesCorruptionEveryTime) {
  for (int i = 0; i < 3; ++i) {
    const std::string e = ErrorOf([] { ProbeContained("bad.h5", "HDF5", [] { raise(SIGSEGV); }); });
    EXPECT_NE(e.find("bad.h5: corrupt (the HDF5 library failed reading it: "), std::string::npos) << e;
  }
}

// Sanitizers reserve terabytes of address space: there the child runs
// uncapped (io/contained.cc) and only the time bound is checked.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kAddressCapped = false;
#else
constexpr bool kAddressCapped = true;
#endif

TEST(Contained, MemoryAndTimeAreBounded) {
  const ContainLimits limits{std::size_t{256} << 20, 1.0};
  if (kAddressCapped) {
    const std::string mem = ErrorOf([&] {
      ProbeContained(
          "big.mat", "matio",
          [] {
            std::vector<char> v(std::size_t{8} << 30);  // 8 GB asked of a 256 MB budget
            v[v.size() - 1] = 1;
          },
          limits);
    });
    EXPECT_NE(mem.find("big.mat: corrupt (the matio library failed reading it"), std::string::npos) << mem;
  }
  const std::string time = ErrorOf([&] {
    ProbeContained(
        "slow.h5", "HDF5", [] { std::this_thread::sleep_for(std::chrono::seconds(30)); }, limits);
  });
  EXPECT_NE(time.find("slow.h5: corrupt (the HDF5 library failed reading it: it did not finish in 1 s)"),
            std::string::npos)
      << time;
}

TEST(Contained, TheProbesOwnErrorAndResultComeBack) {
  EXPECT_EQ(ErrorOf([] { ProbeContained("x.h5", "HDF5", [] { throw Error("x.h5: /log/t_s: missing dataset"); }); }),
            "x.h5: /log/t_s: missing dataset");
  EXPECT_EQ(RunContained("x.h5", "HDF5", [] { return std::string("a\0b", 3); }), std::string("a\0b", 3));
}

// A v5 .mat of a vector and a cell array whose header is patched to claim
// 500 million cells in a file of a few hundred bytes: libmatio sizes its
// table of cells (4 GB of pointers) from the header before it reads one.
// The good vector is read, the damaged cell skipped and listed, and the
// caller's address space does not grow by the claim (it did, to 4 GB,
// before the read was contained).
TEST(Contained, AMatHeaderClaimingGigabytesCostsTheCallerNothing) {
  test::TempDir dir;
  const std::string path = dir / "claims.mat";
  {
    mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, MAT_FT_MAT5);
    ASSERT_NE(mat, nullptr);
    double x[3] = {1, 2, 3};
    std::size_t dims[2] = {3, 1};
    matvar_t* v = Mat_VarCreate("x", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, x, 0);
    Mat_VarWrite(mat, v, MAT_COMPRESSION_NONE);
    Mat_VarFree(v);
    std::size_t one[2] = {1, 1};
    matvar_t* cells[1] = {Mat_VarCreate(nullptr, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, one, x, 0)};
    matvar_t* cell = Mat_VarCreate("c", MAT_C_CELL, MAT_T_CELL, 2, one, cells, 0);
    Mat_VarWrite(mat, cell, MAT_COMPRESSION_NONE);
    Mat_VarFree(cell);
    Mat_Close(mat);
  }
  std::string bytes = test::ReadText(path);
  const std::int32_t want[2] = {1, 1}, claim[2] = {500000000, 1};
  const auto at = bytes.find(std::string(reinterpret_cast<const char*>(want), sizeof want), 128);
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at, sizeof claim, std::string(reinterpret_cast<const char*>(claim), sizeof claim));
  test::WriteText(path, bytes);
  const std::size_t before = PeakBytes();
  for (int i = 0; i < 3; ++i) {
    const MatContents c = ReadMatVectors(path);
    ASSERT_NE(c.Find("x"), nullptr) << c.Names();
    EXPECT_EQ(c.Find("x")->values, (std::vector<double>{1, 2, 3}));
    EXPECT_EQ(c.Find("c"), nullptr);
    std::string skipped;
    for (const auto& k : c.skipped) skipped += k + "; ";
    EXPECT_NE(skipped.find("c: "), std::string::npos) << skipped;
  }
  EXPECT_LT(PeakBytes(), before + (std::size_t{512} << 20));
}

// Writes a minimal run archive, then replaces one dataset by one of the
// given HDF5 type (the values written through HDF5's conversion).
void WriteWithType(const std::string& path, const char* dataset, hid_t type) {
  RunArchive run;
  run.profiles.t_s = {0.0, 0.005};
  run.profiles.encoder = {1, 2};
  run.profiles.points = 3;
  run.profiles.shared_x = true;
  run.profiles.x_mm = {-1, 0, 1};
  run.profiles.z_mm = {0, 1, 0, 0, 1, 0};
  WriteRunArchive(path, run);
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  H5Ldelete(f, dataset, H5P_DEFAULT);
  hsize_t n = 2;
  const hid_t space = H5Screate_simple(1, &n, nullptr);
  const hid_t ds = H5Dcreate2(f, dataset, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const double values[2] = {0.0, 0.005};
  const std::int64_t counts[2] = {1, 2};
  if (H5Tget_class(type) == H5T_FLOAT)
    H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values);
  else
    H5Dwrite(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, counts);
  H5Dclose(ds), H5Sclose(space), H5Fclose(f);
}

TEST(Contained, NumberTypesOtherThanTheFormatsAreRefused) {
  test::TempDir dir;
  const hid_t odd_float = H5Tcopy(H5T_IEEE_F64LE);
  H5Tset_ebias(odd_float, 1000);  // not IEEE's 1023
  WriteWithType(dir / "float.h5", "/profiles/t_s", odd_float);
  H5Tclose(odd_float);
  const std::string f = ErrorOf([&] { ReadRunArchive(dir / "float.h5"); });
  EXPECT_NE(f.find("/profiles/t_s: wrong type: a floating-point layout other than IEEE float32 or float64"),
            std::string::npos)
      << f;
  const hid_t odd_int = H5Tcopy(H5T_STD_I32LE);
  H5Tset_precision(odd_int, 24);
  WriteWithType(dir / "int.h5", "/profiles/encoder", odd_int);
  H5Tclose(odd_int);
  const std::string i = ErrorOf([&] { ReadRunArchive(dir / "int.h5"); });
  EXPECT_NE(i.find("/profiles/encoder: wrong type: an integer layout other than 8, 16, 32 or 64 bits (24 bits"),
            std::string::npos)
      << i;
  // The command says the same, exit 1, and `bead measure` writes nothing.
  test::WriteText(dir / "rig.yaml", test::kCliRigYaml);
  auto [status, out] =
      test::RunCli(dir, "measure --rig " + (dir / "rig.yaml") + " " + (dir / "float.h5") + " -o " + (dir / "g.csv"));
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("floating-point layout"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "g.csv"));
}

}  // namespace
}  // namespace bead
