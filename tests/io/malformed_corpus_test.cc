// A corpus of malformed inputs. Each one must be rejected by its reader
// with a bead::Error naming the file and the place, and by the `bead`
// command with exit status 1 and that message, never a crash.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <functional>

#include "libbead/core/error.h"
#include "libbead/io/hdf5_file.h"
#include "libbead/io/profiles_csv.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/io/run_archive.h"
#include "libbead/sim/sim_config.h"
#include "tests/support/expect_rejected.h"
#include "tests/support/run_cli.h"

namespace bead {
namespace {

struct Malformed {
  std::string name;    // file name in the corpus
  std::string expect;  // part of the message
  std::function<void(const std::string&)> make;
};

// Writes an archive from datasets given as (name, values, dims) by kind.
struct H5Writer {
  h5::File f;
  explicit H5Writer(const std::string& path) : f(h5::File::Create(path, path)) {}
  H5Writer& D(const std::string& n, std::vector<double> v, std::vector<hsize_t> d) {
    f.Write(n, v, d);
    return *this;
  }
  H5Writer& F(const std::string& n, std::vector<float> v, std::vector<hsize_t> d) {
    f.Write(n, v, d);
    return *this;
  }
  H5Writer& I(const std::string& n, std::vector<int64_t> v, std::vector<hsize_t> d) {
    f.Write(n, v, d);
    return *this;
  }
};

// A good 2-profile, 3-point archive with one dataset replaced by `patch`.
std::function<void(const std::string&)> Archive(std::function<void(H5Writer&)> patch,
                                                std::vector<std::string> skip = {}) {
  return [patch, skip](const std::string& path) {
    H5Writer w(path);
    auto want = [&](const std::string& n) { return std::find(skip.begin(), skip.end(), n) == skip.end(); };
    if (want("t")) w.D("/profiles/t_s", {0.0, 0.005}, {2});
    if (want("e")) w.I("/profiles/encoder", {1, 2}, {2});
    if (want("x")) w.F("/profiles/x_mm", {-1, 0, 1}, {3});
    if (want("z")) w.F("/profiles/z_mm", {0, 1, 0, 0, 1, 0}, {2, 3});
    patch(w);
  };
}

std::vector<Malformed> Corpus() {
  const float nan = std::nanf(""), inf = INFINITY;
  auto text = [](std::string body) { return [body](const std::string& p) { test::WriteText(p, body); }; };
  return {
      {"empty.h5", "not an HDF5 file", text("")},
      {"text.h5", "not an HDF5 file", text("profile,t_s\n1,2\n")},
      {"truncated.h5", "",
       [](const std::string& p) {
         Archive([](H5Writer&) {})(p + ".full");
         std::string all = test::ReadText(p + ".full");
         std::remove((p + ".full").c_str());
         test::WriteText(p, all.substr(0, all.size() / 2));
       }},
      {"no_z.h5", "/profiles/z_mm: missing dataset", Archive([](H5Writer&) {}, {"z"})},
      {"no_profiles.h5", "/profiles/t_s: missing dataset",
       Archive([](H5Writer& w) { w.D("/other", {1}, {1}); }, {"t", "e", "x", "z"})},
      {"float_encoder.h5", "/profiles/encoder: wrong type",
       Archive(
           [](H5Writer& w) {
             w.D("/profiles/encoder", {1, 2}, {2});
           },
           {"e"})},
      {"int_z.h5", "/profiles/z_mm: wrong type",
       Archive(
           [](H5Writer& w) {
             w.I("/profiles/z_mm", {0, 1, 0, 0, 1, 0}, {2, 3});
           },
           {"z"})},
      {"z_1d.h5", "/profiles/z_mm: wrong shape",
       Archive(
           [](H5Writer& w) {
             w.F("/profiles/z_mm", {0, 1, 0, 0, 1, 0}, {6});
           },
           {"z"})},
      {"t_2d.h5", "/profiles/t_s: wrong shape",
       Archive(
           [](H5Writer& w) {
             w.D("/profiles/t_s", {0, 1}, {1, 2});
           },
           {"t"})},
      {"z_rows.h5", "/profiles/z_mm: wrong shape: 3 rows",
       Archive(
           [](H5Writer& w) {
             w.F("/profiles/z_mm", {0, 1, 0, 0, 1, 0, 0, 0, 0}, {3, 3});
           },
           {"z"})},
      {"x_points.h5", "/profiles/x_mm: wrong shape: 2 points",
       Archive(
           [](H5Writer& w) {
             w.F("/profiles/x_mm", {0, 1}, {2});
           },
           {"x"})},
      {"encoder_length.h5", "/profiles/encoder: length mismatch",
       Archive(
           [](H5Writer& w) {
             w.I("/profiles/encoder", {1, 2, 3}, {3});
           },
           {"e"})},
      {"nan_time.h5", "/profiles/t_s[1]: time is not finite",
       Archive(
           [](H5Writer& w) {
             w.D("/profiles/t_s", {0.0, NAN}, {2});
           },
           {"t"})},
      {"unsorted_time.h5", "/profiles/t_s[1]: time does not increase",
       Archive(
           [](H5Writer& w) {
             w.D("/profiles/t_s", {1.0, 0.5}, {2});
           },
           {"t"})},
      {"inf_z.h5", "/profiles/z_mm[1, 2]: infinite height",
       Archive(
           [inf](H5Writer& w) {
             w.F("/profiles/z_mm", {0, 1, 0, 0, 1, inf}, {2, 3});
           },
           {"z"})},
      {"log_length.h5", "/log/screw_rpm: length mismatch", Archive([](H5Writer& w) {
         w.D("/log/t_s", {0, 1}, {2}).I("/log/encoder", {0, 1}, {2}).D("/log/screw_rpm", {1}, {1});
       })},
      {"log_missing.h5", "/log/encoder: missing dataset", Archive([](H5Writer& w) {
         w.D("/log/t_s", {0, 1}, {2});
       })},
      {"nan_x_ok_but_inf.h5", "/profiles/x_mm[1]: infinite coordinate",
       Archive(
           [nan, inf](H5Writer& w) {
             w.F("/profiles/x_mm", {nan, inf, 1}, {3});
           },
           {"x"})},
      {"header.csv", "line 1: column 4 of the header is 'x'", text("profile,t_s,encoder,x,z_mm\n0,0,0,1,2\n")},
      {"number.csv", "line 3: column 5 (z_mm) is 'abc', not a number",
       text("profile,t_s,encoder,x_mm,z_mm\n0,0,0,1,2\n0,0,0,2,abc\n")},
      {"short_row.csv", "line 2: has 3 fields", text("profile,t_s,encoder,x_mm,z_mm\n0,0,0\n")},
      {"split_profile.csv", "line 4: rows of profile 0 are not together",
       text("profile,t_s,encoder,x_mm,z_mm\n0,0,0,1,2\n1,1,1,1,2\n0,0,0,2,2\n")},
      {"encoder_changes.csv", "line 3: profile 0 changes its t_s or encoder",
       text("profile,t_s,encoder,x_mm,z_mm\n0,0,0,1,2\n0,0,5,2,2\n")},
      {"time_backwards.csv", "profiles/t_s[1]: time does not increase",
       text("profile,t_s,encoder,x_mm,z_mm\n0,1,0,1,2\n1,0.5,0,1,2\n")},
      {"float_encoder.csv", "line 2: column 3 (encoder) is '1.5', not a whole number",
       text("profile,t_s,encoder,x_mm,z_mm\n0,0,1.5,1,2\n")},
      {"empty.csv", "line 1: empty file", text("")},
      {"header_only.csv", "holds no profile rows", text("profile,t_s,encoder,x_mm,z_mm\n")},
  };
}

TEST(MalformedCorpus, ReadersRejectWithFileAndPlace) {
  test::TempDir dir;
  for (const Malformed& m : Corpus()) {
    const std::string path = dir / m.name;
    m.make(path);
    test::ExpectRejected(path, m.expect, [&] {
      if (path.ends_with(".csv"))
        ReadProfilesCsv(path);
      else
        ReadRunArchive(path);
    });
  }
}

// The command line: every malformed input gives exit status 1 and a one-line
// message naming the file; none crashes (a signal would show as >= 128).
TEST(MalformedCorpus, CommandLineReportsAndDoesNotCrash) {
  test::TempDir dir;
  test::WriteText(dir / "rig.yaml", test::kCliRigYaml);
  test::WriteText(dir / "bad-rig.yaml", "encoder: {counts_per_rev: 0}\n");
  auto corpus = Corpus();
  corpus.push_back({"run.h5", "", Archive([](H5Writer&) {})});
  for (const Malformed& m : corpus) {
    const std::string path = dir / m.name;
    m.make(path);
    const bool good = m.name == "run.h5";
    const std::string rig = good ? dir / "bad-rig.yaml" : dir / "rig.yaml";
    const std::string cmd = std::string(BEAD_CLI) + " measure --rig " + rig + " " + path + " -o " + (dir / "out.csv") +
                            " 2>" + (dir / "stderr.txt") + " >/dev/null";
    const int status = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(status)) << m.name;
    EXPECT_EQ(WEXITSTATUS(status), 1) << m.name;
    const std::string err = test::ReadText(dir / "stderr.txt");
    EXPECT_EQ(err.rfind("bead: error: ", 0), 0u) << m.name << ": " << err;
    EXPECT_NE(err.find(good ? rig : path), std::string::npos) << m.name << ": " << err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out.csv")) << m.name;
  }
}

// What the fuzzers found (testdata/malformed/README.md), kept after the fix.
TEST(MalformedCorpus, FuzzFindingsStayFixed) {
  const std::string d = std::string(BEAD_SOURCE_DIR) + "/testdata/malformed/";
  test::ExpectRejected(d + "huge_shape.h5", "/profiles/x_mm: declares [2533274790395925, 24] values",
                       [&] { ReadRunArchive(d + "huge_shape.h5"); });
  test::ExpectRejected(d + "huge_type.h5", "/profiles/encoder: wrong type: an integer layout other than",
                       [&] { ReadRunArchive(d + "huge_type.h5"); });
  test::ExpectRejected(d + "huge_integer.yaml", "encoder.bits: is out of range",
                       [&] { ReadRigFile(d + "huge_integer.yaml"); });
  test::ExpectRejected(d + "sim_sequence_key.yaml", "line 3: pins.<key>: must be plain text",
                       [&] { sim::ReadSimConfig(d + "sim_sequence_key.yaml"); });
  // A scan numbered -1 (the reader's "no scan yet"): read as the scan it is.
  const PinScanArchive pins = ReadPinScansCsv(d + "pins_scan_minus_one.csv");
  ASSERT_EQ(pins.scans.size(), 1u);
  EXPECT_EQ(pins.scans[0].profiles.size(), 1u);
}

}  // namespace
}  // namespace bead
