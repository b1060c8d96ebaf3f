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
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include "libbead/core/error.h"
#include "libbead/io/contained.h"
#include "libbead/io/mat_file.h"
#include "libbead/io/run_archive.h"
#include "tests/support/run_cli.h"
#include "tests/support/expect_rejected.h"
#include "tests/support/temp_dir.h"

namespace bead {
namespace {

using test::ErrorOf;

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
const bool kAddressCapped = AddressSpaceCapped();

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

// A probe blocked (a lock another thread held when it was forked, which
// no thread of the child will release) is forked again, not called
// corrupt: the first child here sleeps forever, the second finds the
// first's mark and finishes. One that sleeps in every child is still
// bounded by the wall time.
TEST(Contained, ABlockedProbeIsForkedAgainAndAlwaysBlockedIsStillBounded) {
  test::TempDir dir;
  const std::string mark = dir / "first_child_was_here";
  const std::string result = RunContained("locked.h5", "HDF5", [&] {
    if (!std::filesystem::exists(mark)) {
      std::ofstream(mark) << "1\n";
      for (;;) std::this_thread::sleep_for(std::chrono::seconds(60));
    }
    return std::string("read");
  });
  EXPECT_EQ(result, "read");
  ContainLimits limits;
  limits.seconds = 3;
  const std::string e = ErrorOf([&] {
    ProbeContained(
        "asleep.h5", "HDF5", [] { std::this_thread::sleep_for(std::chrono::seconds(60)); }, limits);
  });
  EXPECT_NE(e.find("asleep.h5: corrupt (the HDF5 library failed reading it: it did not finish in 3 s)"),
            std::string::npos)
      << e;
}

// A probe that keeps working when its wall time is up, only slowly (a
// loaded machine starves it of the CPU), is given more time while its CPU
// time rises: here it works 5 ms in every 25 for 2.5 s against a 1-s
// limit, and its answer comes back. One that works so forever is still
// bounded, at six times its wall time.
void WorkSlowly(double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    const auto burst = std::chrono::steady_clock::now() + std::chrono::milliseconds(5);
    volatile unsigned long spin = 0;
    while (std::chrono::steady_clock::now() < burst) spin = spin + 1;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

TEST(Contained, AProbeStarvedOfTheCpuIsGivenTimeWhileItWorks) {
  ContainLimits limits;
  limits.seconds = 1;
  const std::string result = RunContained(
      "starved.h5", "HDF5",
      [] {
        WorkSlowly(2.5);
        return std::string("read");
      },
      limits);
  EXPECT_EQ(result, "read");
  const std::string e = ErrorOf([&] {
    ProbeContained(
        "forever.h5", "HDF5", [] { WorkSlowly(1e6); }, limits);
  });
  EXPECT_NE(e.find("forever.h5: corrupt (the HDF5 library failed reading it: it did not finish in 6 s)"),
            std::string::npos)
      << e;
}

// A probe kept busy (a damaged file can loop libhdf5) is stopped by its
// CPU-time limit well before the wall-time one.
TEST(Contained, CpuTimeIsBounded) {
  ContainLimits limits;
  limits.seconds = 60, limits.cpu_seconds = 1;
  const auto start = std::chrono::steady_clock::now();
  const std::string e = ErrorOf([&] {
    ProbeContained(
        "busy.h5", "HDF5",
        [] {
          volatile unsigned long spin = 0;
          for (;;) spin = spin + 1;
        },
        limits);
  });
  EXPECT_NE(e.find("busy.h5: corrupt (the HDF5 library failed reading it: it used more than 1 s of CPU time)"),
            std::string::npos)
      << e;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 30.0);
}

// Whether process `pid` is gone (or a zombie: it runs no more).
bool Gone(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string pid_field, name, state;
  if (!(stat >> pid_field >> name >> state)) return true;
  return state == "Z" || state == "X";
}

// A caller killed while its probe spins takes the probe with it: no probe
// is left running under init.
TEST(Contained, TheProbeDiesWithItsCaller) {
  test::TempDir dir;
  const std::string pid_file = dir / "probe.pid";
  const pid_t caller = fork();
  ASSERT_GE(caller, 0);
  if (caller == 0) {
    try {
      ProbeContained("spin.h5", "HDF5", [&] {
        std::ofstream(pid_file + ".tmp") << getpid() << "\n";
        std::rename((pid_file + ".tmp").c_str(), pid_file.c_str());
        volatile unsigned long spin = 0;
        for (;;) spin = spin + 1;
      });
    } catch (...) {
    }
    _exit(0);
  }
  pid_t probe = 0;
  for (int i = 0; i < 500 && probe == 0; ++i) {
    std::ifstream in(pid_file);
    if (!(in >> probe)) probe = 0, std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_GT(probe, 0);
  EXPECT_FALSE(Gone(probe));
  kill(caller, SIGKILL);
  waitpid(caller, nullptr, 0);
  bool gone = false;
  for (int i = 0; i < 300 && !gone; ++i) {
    gone = Gone(probe);
    if (!gone) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_TRUE(gone) << "the probe " << probe << " outlived its caller";
  if (!gone) kill(probe, SIGKILL);
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
    // Under a sanitizer the child runs uncapped (kAddressCapped): libmatio
    // then walks the claimed cells until the CPU bound, which a slower
    // machine reaches first (8 s; a CI run reached it once): the
    // file is then refused whole, with that said, and the caller still pays
    // nothing.
    MatContents c;
    try {
      c = ReadMatVectors(path);
    } catch (const Error& e) {
      ASSERT_FALSE(kAddressCapped) << e.what();
      EXPECT_NE(std::string(e.what()).find("claims.mat: corrupt (the matio library failed reading it: it used more "
                                           "than"),
                std::string::npos)
          << e.what();
      continue;
    }
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

// A run archive whose profile chunks declare 200 MB each for a dataset of
// six values (a damaged chunk header: the streamed reader inflates a chunk
// whole, so it would allocate that much per worker) is refused by name
// before anything is allocated, by the library and by the command.
TEST(Contained, AChunkFarBeyondItsDatasetIsRefused) {
  test::TempDir dir;
  const std::string path = dir / "chunk.h5";
  WriteWithType(path, "/profiles/t_s", H5T_IEEE_F64LE);
  {
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    H5Ldelete(f, "/profiles/z_mm", H5P_DEFAULT);
    hsize_t dims[2] = {2, 3}, max[2] = {H5S_UNLIMITED, 3}, chunk[2] = {hsize_t{1} << 24, 3};
    const hid_t space = H5Screate_simple(2, dims, max);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, 2, chunk);
    H5Pset_deflate(dcpl, 1);
    const hid_t ds = H5Dcreate2(f, "/profiles/z_mm", H5T_IEEE_F32LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    const float z[6] = {0, 1, 0, 0, 1, 0};
    H5Dwrite(ds, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, z);
    H5Dclose(ds), H5Pclose(dcpl), H5Sclose(space), H5Fclose(f);
  }
  const std::size_t before = PeakBytes();
  const std::string e = ErrorOf([&] { ReadRunArchive(path); });
  EXPECT_NE(e.find("/profiles/z_mm: damaged: its chunks declare 201326592 bytes each for a dataset of 6 values"),
            std::string::npos)
      << e;
  if (kAddressCapped) {
    EXPECT_LT(PeakBytes(), before + (std::size_t{100} << 20));
  }
  // The command answers in one line, exit 1, under an address-space cap of
  // 2 GB (where no sanitizer reserves its shadow).
  test::WriteText(dir / "rig.yaml", test::kCliRigYaml);
  const std::string cap = kAddressCapped ? "ulimit -v 2000000; " : "";
  const int status = std::system(("/bin/sh -c '" + cap + BEAD_CLI + " measure --rig " + (dir / "rig.yaml") + " " +
                                  path + " -o " + (dir / "g.csv") + " >" + (dir / "out.txt") + " 2>&1'")
                                     .c_str());
  const std::string out = test::ReadText(dir / "out.txt");
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << out;
  EXPECT_NE(out.find("damaged: its chunks declare"), std::string::npos) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "g.csv"));
}

}  // namespace
}  // namespace bead
