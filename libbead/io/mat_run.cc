#include "libbead/io/mat_run.h"

#include <cmath>
#include <filesystem>
#include <limits>

#include "libbead/core/error.h"
#include "libbead/io/mat_file.h"

namespace bead {
namespace {

std::string Shape(const MatMatrix& m) { return std::to_string(m.rows) + " x " + std::to_string(m.cols); }

float Coordinate(double v) {
  return std::isfinite(v) ? static_cast<float>(v) : std::numeric_limits<float>::quiet_NaN();
}

}  // namespace

ImportedRun ReadMatRun(const std::string& path, const ImportColumns& c) {
  CheckImportColumns(path, c, false);
  const MatMatrix time = ReadMatMatrix(path, c.time);
  const MatMatrix z = ReadMatMatrix(path, c.z);
  const MatMatrix x = ReadMatMatrix(path, c.x);
  if (time.rows != 1 && time.cols != 1)
    throw Error(Located(path, c.time, "the time must be a vector, not a " + Shape(time) + " matrix"));
  const std::size_t n = time.values.size();
  // Profiles as rows (N x P) or, when only that fits, as columns (P x N).
  const bool by_row = z.rows == n;
  if (!by_row && z.cols != n)
    throw Error(
        Located(path, c.z,
                "is " + Shape(z) + ": neither side matches the " + std::to_string(n) + " times of '" + c.time + "'"));
  const std::size_t p = by_row ? z.cols : z.rows;
  auto z_at = [&](std::size_t i, std::size_t k) { return by_row ? z.at(i, k) : z.at(k, i); };
  const bool x_shared = (x.rows == 1 || x.cols == 1) && x.values.size() == p && !(x.rows == z.rows && x.cols == z.cols);
  if (!x_shared && !(x.rows == z.rows && x.cols == z.cols))
    throw Error(Located(path, c.x,
                        "is " + Shape(x) + ": x is a vector of " + std::to_string(p) +
                            " values or a matrix shaped as '" + c.z + "' (" + Shape(z) + ")"));

  ImportedRun result;
  ProfileBlock& b = result.run.profiles;
  b.points = p;
  b.shared_x = x_shared;
  const float sign = c.z_is_distance ? -1.0f : 1.0f;
  if (x_shared)
    for (double v : x.values) b.x_mm.push_back(Coordinate(v));
  b.z_mm.reserve(n * p);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = time.values[i] * c.time_scale;
    if (!std::isfinite(t))
      throw Error(Located(path, c.time + "(" + std::to_string(i + 1) + ")", "the time is not finite"));
    b.t_s.push_back(t);
    for (std::size_t k = 0; k < p; ++k) {
      b.z_mm.push_back(sign * Coordinate(z_at(i, k)));
      if (!x_shared) b.x_mm.push_back(Coordinate(by_row ? x.at(i, k) : x.at(k, i)));
    }
  }
  if (!c.encoder.empty()) {
    const MatMatrix e = ReadMatMatrix(path, c.encoder);
    if ((e.rows != 1 && e.cols != 1) || e.values.size() != n)
      throw Error(
          Located(path, c.encoder,
                  "is " + Shape(e) + ": the encoder is a vector of " + std::to_string(n) + " readings, one per time"));
    for (std::size_t i = 0; i < n; ++i) {
      const double v = e.values[i];
      if (!(std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 9.0e15))
        throw Error(Located(path, c.encoder + "(" + std::to_string(i + 1) + ")", "the encoder is not a whole number"));
      b.encoder.push_back(static_cast<int64_t>(v));
    }
  } else {
    b.encoder.assign(n, 0);
    result.run.attributes[kEncoderAttribute] = kEncoderAbsent;
  }
  result.rows = n * p;
  ValidateProfileBlock(b, path, c.z);
  result.run.attributes["imported_from"] = std::filesystem::path(path).filename().string();
  return result;
}

}  // namespace bead
