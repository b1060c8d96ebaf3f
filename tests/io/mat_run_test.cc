// Runs stored in MATLAB .mat files as matrices (as an acquisition in MATLAB
// saves them): a twin run written by libmatio (v5 and v7.3, profiles as
// rows or as columns, x shared or per profile) comes back point for point
// and measures the same as the archive it came from; files whose shapes
// do not fit, or whose encoder is not whole counts, say which variable and why.
#include "libbead/io/mat_run.h"

#include <gtest/gtest.h>
#include <matio.h>

#include <cmath>
#include <vector>

#include "libbead/io/run_archive.h"
#include "tests/support/expect_rejected.h"
#include "tests/support/run_cli.h"

namespace bead {
namespace {

void WriteMatrix(mat_t* mat, const char* name, std::size_t rows, std::size_t cols, const std::vector<double>& v) {
  std::size_t dims[2] = {rows, cols};
  matvar_t* var = Mat_VarCreate(name, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, const_cast<double*>(v.data()), 0);
  ASSERT_NE(var, nullptr);
  ASSERT_EQ(Mat_VarWrite(mat, var, MAT_COMPRESSION_ZLIB), 0) << name;
  Mat_VarFree(var);
}

// The run's profiles as MATLAB matrices (column-major): Z N x P
// (by_row) or P x N, X a row vector of P or a matrix as Z, t and enc N x 1.
void WriteRunMat(const std::string& path, mat_ft version, const ProfileBlock& b, bool by_row, bool x_matrix) {
  mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, version);
  ASSERT_NE(mat, nullptr) << path;
  const std::size_t n = b.size(), p = b.points;
  std::vector<double> z(n * p), x(x_matrix ? n * p : p), t(b.t_s), enc(b.encoder.begin(), b.encoder.end());
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < p; ++k) {
      const std::size_t at = by_row ? i + n * k : k + p * i;
      z[at] = b.view(i).z_mm[k];
      if (x_matrix) x[at] = b.view(i).x_mm[k];
    }
  if (!x_matrix)
    for (std::size_t k = 0; k < p; ++k) x[k] = b.view(0).x_mm[k];
  WriteMatrix(mat, "Z", by_row ? n : p, by_row ? p : n, z);
  WriteMatrix(mat, "X", x_matrix ? (by_row ? n : p) : 1, x_matrix ? (by_row ? p : n) : p, x);
  WriteMatrix(mat, "t", n, 1, t);
  WriteMatrix(mat, "enc", n, 1, enc);
  Mat_Close(mat);
}

bool SameFloat(float a, float b) { return a == b || (std::isnan(a) && std::isnan(b)); }

TEST(MatRun, TwinRunComesBackPointForPoint) {
  test::TempDir dir;
  test::WriteText(dir / "sim.yaml", "seed: 3\nduration_s: 1\nsensor: {points: 160}\npins: {scans: 0}\n");
  auto [sim, sim_out] = test::RunCli(dir, "simulate " + (dir / "sim.yaml") + " -o " + (dir / "twin"));
  ASSERT_EQ(sim, 0) << sim_out;
  const ProfileBlock b = ReadRunArchive(dir / "twin/run.h5", true, false).profiles;
  ASSERT_GT(b.size(), 100u);
  const ImportColumns columns = Columns("", "t", "X", "Z", "enc", 1.0, false);
  struct Case {
    mat_ft version;
    bool by_row, x_matrix;
  };
  // The last case is the run itself (x per profile): it goes through the command line below.
  for (const Case c :
       {Case{MAT_FT_MAT5, true, false}, Case{MAT_FT_MAT5, false, false}, Case{MAT_FT_MAT73, false, true}}) {
    SCOPED_TRACE(std::to_string(c.version) + (c.by_row ? " rows" : " columns") +
                 (c.x_matrix ? " x matrix" : " x shared"));
    const std::string path = dir / "run.mat";
    WriteRunMat(path, c.version, b, c.by_row, c.x_matrix);
    const ImportedRun r = ReadMatRun(path, columns);
    const ProfileBlock& m = r.run.profiles;
    ASSERT_EQ(m.size(), b.size());
    ASSERT_EQ(m.points, b.points);
    EXPECT_EQ(m.shared_x, !c.x_matrix);
    EXPECT_FALSE(EncoderAbsent(r.run));
    for (std::size_t i = 0; i < b.size(); ++i) {
      ASSERT_EQ(m.t_s[i], b.t_s[i]);
      ASSERT_EQ(m.encoder[i], b.encoder[i]);
      for (std::size_t k = 0; k < b.points; ++k) {
        ASSERT_TRUE(SameFloat(m.view(i).z_mm[k], b.view(i).z_mm[k])) << i << "," << k;
        // A shared x is the first profile's (what the file was given).
        const float x = b.view(c.x_matrix ? i : 0).x_mm[k];
        ASSERT_TRUE(SameFloat(m.view(i).x_mm[k], x)) << i << "," << k;
      }
    }
  }
  // Through the command line: the same geometry as the archive's.
  const std::string rig = dir / "twin/rig.yaml";
  auto [im, im_out] = test::RunCli(dir, "import " + (dir / "run.mat") + " -o " + (dir / "back.h5") +
                                            " --time-column t --x-column X --z-column Z --encoder-column enc");
  ASSERT_EQ(im, 0) << im_out;
  auto [g0, o0] = test::RunCli(
      dir, "measure --occlusion none --rig " + rig + " " + (dir / "twin/run.h5") + " -o " + (dir / "g0.csv"));
  auto [g1, o1] =
      test::RunCli(dir, "measure --occlusion none --rig " + rig + " " + (dir / "back.h5") + " -o " + (dir / "g1.csv"));
  ASSERT_EQ(g0, 0) << o0;
  ASSERT_EQ(g1, 0) << o1;
  EXPECT_EQ(test::ReadText(dir / "g0.csv"), test::ReadText(dir / "g1.csv"));
}

TEST(MatRun, ShapesThatDoNotFitAndFractionalCountsAreNamed) {
  test::TempDir dir;
  const std::string path = dir / "bad.mat";
  mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, MAT_FT_MAT5);
  ASSERT_NE(mat, nullptr);
  WriteMatrix(mat, "Z", 3, 4, std::vector<double>(12, 1.0));
  WriteMatrix(mat, "X", 1, 5, std::vector<double>(5, 0.0));
  WriteMatrix(mat, "X4", 1, 4, {0.0, 1.0, 2.0, 3.0});
  WriteMatrix(mat, "t", 3, 1, {0.0, 0.1, 0.2});
  WriteMatrix(mat, "t5", 5, 1, {0.0, 0.1, 0.2, 0.3, 0.4});
  WriteMatrix(mat, "enc", 3, 1, {0.0, 1.5, 2.0});
  Mat_Close(mat);
  test::ExpectRejected(path, "X: is 1 x 5: x is a vector of 4 values or a matrix shaped as 'Z' (3 x 4)",
                       [&] { ReadMatRun(path, Columns("", "t", "X", "Z", "", 1.0, false)); });
  test::ExpectRejected(path, "Z: is 3 x 4: neither side matches the 5 times of 't5'",
                       [&] { ReadMatRun(path, Columns("", "t5", "X", "Z", "", 1.0, false)); });
  test::ExpectRejected(path, "height: no such variable (its numeric variables: Z, X, X4, t, t5, enc)",
                       [&] { ReadMatRun(path, Columns("", "t", "X", "height", "", 1.0, false)); });
  test::ExpectRejected(path, "enc(2): the encoder is not a whole number",
                       [&] { ReadMatRun(path, Columns("", "t", "X4", "Z", "enc", 1.0, false)); });
  test::WriteText(dir / "text.mat", "not a mat file at all, only text\n");
  test::ExpectRejected(dir / "text.mat", "not a MATLAB .mat file",
                       [&] { ReadMatRun(dir / "text.mat", Columns("", "t", "X", "Z", "", 1.0, false)); });
}

}  // namespace
}  // namespace bead
