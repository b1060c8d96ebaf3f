// `bead identify` on weld-style runs whose input has its own file and
// clock, validated on a second run: that run needs its own input file (it
// must never be paired with the first run's input), and the arc's strike
// is reported as a start from rest.
#include <gtest/gtest.h>
#include <matio.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

#include "libbead/model/identify.h"
#include "tests/support/random_steps.h"
#include "tests/support/run_cli.h"

namespace bead::model {
namespace {

// Width (0 until the arc strikes at 3 s, then K u(t - Td) through 1/(T s + 1)
// from rest) every 0.04 s; the wire feed in steps on its own 4 ms clock.
struct WeldRun {
  std::vector<double> tu, u, ty, w;
};
WeldRun MakeRun(unsigned seed) {
  WeldRun r;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.02);
  const auto [tu, u] = test::RandomSteps(rng, 3.0, 7.0, 10001, 300, 0.004);
  std::vector<double> uy;
  for (int i = 0; i < 1000; ++i) {
    r.ty.push_back(0.04 * i);
    uy.push_back(u[static_cast<std::size_t>(std::lround(std::floor(r.ty.back() / 0.004 + 1e-9)))]);
  }
  Segment arc{75, r.ty.size(), true};  // at rest at 3.00 s
  const std::vector<double> w = Predict({{1.2}, {0.5, 1.0}, 0.1}, 0.0, r.ty, uy, {}, {arc});
  for (std::size_t i = 0; i < r.ty.size(); ++i) r.w.push_back(i < arc.begin ? 0.0 : w[i] + noise(rng));
  r.tu = tu, r.u = u;
  return r;
}

void WriteRun(const test::TempDir& dir, const std::string& name, unsigned seed) {
  const WeldRun r = MakeRun(seed);
  std::string wcsv = "t,w\n", ucsv = "t,wfs\n";
  for (std::size_t i = 0; i < r.ty.size(); ++i) wcsv += std::to_string(r.ty[i]) + "," + std::to_string(r.w[i]) + "\n";
  for (std::size_t i = 0; i < r.tu.size(); ++i) ucsv += std::to_string(r.tu[i]) + "," + std::to_string(r.u[i]) + "\n";
  test::WriteText(dir / (name + "_w.csv"), wcsv);
  test::WriteText(dir / (name + "_wfs.csv"), ucsv);
}

// The same run as a MATLAB acquisition saves it: the two series on their
// own clocks beside what a reader must skip (a cell array, text, a matrix;
// libmatio writes no name twice, so that case is left to the real files).
void WriteMat(const std::string& path, mat_ft version, const WeldRun& r) {
  mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, version);
  ASSERT_NE(mat, nullptr) << path;
  auto vec = [&](const char* name, const std::vector<double>& v) {
    std::size_t dims[2] = {v.size(), 1};
    matvar_t* var = Mat_VarCreate(name, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, const_cast<double*>(v.data()), 0);
    ASSERT_NE(var, nullptr);
    ASSERT_EQ(Mat_VarWrite(mat, var, MAT_COMPRESSION_NONE), 0) << name;
    Mat_VarFree(var);
  };
  vec("width_time", r.ty);
  vec("width", r.w);
  const std::vector<double> grid(12, 1.0);
  std::size_t mdims[2] = {3, 4};
  matvar_t* m = Mat_VarCreate("calibration", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, mdims, const_cast<double*>(grid.data()), 0);
  Mat_VarWrite(mat, m, MAT_COMPRESSION_NONE);
  Mat_VarFree(m);
  char text[] = "operator notes";
  std::size_t tdims[2] = {1, sizeof text - 1};
  matvar_t* t = Mat_VarCreate("notes", MAT_C_CHAR, MAT_T_UINT8, 2, tdims, text, 0);
  Mat_VarWrite(mat, t, MAT_COMPRESSION_NONE);
  Mat_VarFree(t);
  std::size_t cdims[2] = {1, 1};
  matvar_t* cells[1] = {
      Mat_VarCreate(nullptr, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, cdims, const_cast<double*>(grid.data()), 0)};
  matvar_t* cell = Mat_VarCreate("state_struct", MAT_C_CELL, MAT_T_CELL, 2, cdims, cells, 0);
  Mat_VarWrite(mat, cell, MAT_COMPRESSION_NONE);
  Mat_VarFree(cell);
  vec("wfs_time", r.tu);
  vec("wfs", r.u);
  Mat_Close(mat);
}

TEST(IdentifyCommand, ValidationRunWithItsOwnInputFile) {
  test::TempDir dir;
  WriteRun(dir, "a", 1);
  WriteRun(dir, "b", 2);
  const std::string common = "identify " + (dir / "a_w.csv") + " --time t --output w --input wfs --input-file " +
                             (dir / "a_wfs.csv") + " --structure P1D --validate " + (dir / "b_w.csv");
  auto [status, out] = test::RunCli(dir, common + " -o " + (dir / "m.json"));
  EXPECT_NE(status, 0) << out;
  EXPECT_NE(out.find("--validate-input-file"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "m.json"));
  std::tie(status, out) =
      test::RunCli(dir, common + " --validate-input-file " + (dir / "b_wfs.csv") + " -o " + (dir / "m.json"));
  ASSERT_EQ(status, 0) << out;
  // Noise 0.02 against a width that varies by ~1.2 (std): fit ~98 %; the
  // input joined at the output's times costs at most a sample's timing.
  const auto at = out.find("fit on validation data");
  ASSERT_NE(at, std::string::npos) << out;
  const double fit = std::stod(out.substr(out.find("): ", at) + 3));
  EXPECT_GT(fit, 95.0) << out;
  const auto j = nlohmann::json::parse(test::ReadText(dir / "m.json"));
  ASSERT_EQ(j["initial_state"].size(), 1u);
  EXPECT_EQ(j["initial_state"][0]["from"], "rest: the process started");
  EXPECT_NEAR(j["initial_state"][0]["t_s"].get<double>(), 3.0, 1e-6);
}

// The order table, scored on the validation run: the true order (one
// pole, no zero) fits the held-out run within the noise's ~2 % of the
// best row, and no order scores above the noise's ceiling (~98 %).
TEST(IdentifyCommand, OrderTableScoresOnTheValidationRun) {
  test::TempDir dir;
  WriteRun(dir, "a", 3);
  WriteRun(dir, "b", 4);
  const auto [status, out] = test::RunCli(
      dir, "identify " + (dir / "a_w.csv") + " --time t --output w --input wfs --input-file " + (dir / "a_wfs.csv") +
               " --validate " + (dir / "b_w.csv") + " --validate-input-file " + (dir / "b_wfs.csv") + " --orders");
  ASSERT_EQ(status, 0) << out;
  std::istringstream lines(out.substr(out.find("fit_val_%")));
  std::string line;
  std::getline(lines, line);
  double best = -1e9, first_order = NAN;
  int rows = 0;
  for (int poles, zeros; std::getline(lines, line);) {
    double est, val, aicc, delay;
    if (std::sscanf(line.c_str(), "%d %d %lf %lf %lf %lf", &poles, &zeros, &est, &val, &aicc, &delay) != 6) break;
    ++rows;
    best = std::max(best, val);
    if (poles == 1 && zeros == 0) first_order = val;
  }
  ASSERT_GT(rows, 3) << out;
  ASSERT_TRUE(std::isfinite(first_order)) << out;
  EXPECT_GT(first_order, best - 2.0) << out;
  EXPECT_LT(best, 99.5) << out;
}

// A .mat straight into identify, as v5 and as v7.3 (HDF5): the same model
// as the CSV pair of the same numbers (to the CSV's 6 printed decimals),
// what is skipped said, and the two clocks' different lengths named when
// --input-time is missing.
TEST(IdentifyCommand, ReadsMatlabFilesWithTwoClocks) {
  test::TempDir dir;
  const WeldRun r = MakeRun(3);
  WriteRun(dir, "c", 3);
  auto [cs, cout_] =
      test::RunCli(dir, "identify " + (dir / "c_w.csv") + " --time t --output w --input wfs --input-file " +
                            (dir / "c_wfs.csv") + " --structure P1D -o " + (dir / "csv.json"));
  ASSERT_EQ(cs, 0) << cout_;
  const auto from_csv = nlohmann::json::parse(test::ReadText(dir / "csv.json"));
  for (auto [version, name] : {std::pair{MAT_FT_MAT5, "v5.mat"}, std::pair{MAT_FT_MAT73, "v73.mat"}}) {
    WriteMat(dir / name, version, r);
    auto [status, out] = test::RunCli(dir, "identify " + (dir / name) +
                                               " --input wfs --input-time wfs_time --output width "
                                               "--output-time width_time --structure P1D -o " +
                                               (dir / "mat.json"));
    ASSERT_EQ(status, 0) << out;
    EXPECT_NE(out.find("skipped what is no numeric vector"), std::string::npos) << out;
    EXPECT_NE(out.find("calibration: a matrix"), std::string::npos) << out;
    EXPECT_NE(out.find("state_struct: a cell array"), std::string::npos) << out;
    EXPECT_NE(out.find("notes: text"), std::string::npos) << out;
    const auto j = nlohmann::json::parse(test::ReadText(dir / "mat.json"));
    // The truth: K 1.2, T 0.5 s, delay 0.1 s; noise 0.02 on 925 samples.
    const double k = j["num"][0].get<double>() / j["den"].back().get<double>();
    EXPECT_NEAR(k, 1.2, 0.02) << j.dump();
    EXPECT_NEAR(j["delay_s"].get<double>(), 0.1, 0.02) << j.dump();
    EXPECT_NEAR(k, from_csv["num"][0].get<double>() / from_csv["den"].back().get<double>(), 1e-4) << j.dump();
    EXPECT_NEAR(j["delay_s"].get<double>(), from_csv["delay_s"].get<double>(), 1e-6);
  }
  auto [ex, ex_out] = test::RunCli(dir, "explain " + (dir / "v73.mat") +
                                            " --input wfs --input-time wfs_time --output "
                                            "width --output-time width_time --structure P1D -o " +
                                            (dir / "explain.json"));
  EXPECT_EQ(ex, 0) << ex_out;
  EXPECT_NE(ex_out.find("held at each of the output's times"), std::string::npos) << ex_out;
  auto [bad, bad_out] =
      test::RunCli(dir, "identify " + (dir / "v5.mat") + " --input wfs --output width --time width_time");
  EXPECT_NE(bad, 0);
  EXPECT_NE(bad_out.find("different clocks"), std::string::npos) << bad_out;
  auto [missing, missing_out] =
      test::RunCli(dir, "identify " + (dir / "v5.mat") + " --input feed --output width --time width_time");
  EXPECT_NE(missing, 0);
  EXPECT_NE(missing_out.find("no numeric vector 'feed' (vectors: width_time, width, wfs_time, wfs)"), std::string::npos)
      << missing_out;
}

}  // namespace
}  // namespace bead::model
