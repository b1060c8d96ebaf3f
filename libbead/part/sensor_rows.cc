#include "libbead/part/sensor_rows.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace bead::part {
namespace {

// A row's values asked of memory ahead of their use (for writing: 1).
template <int kWrite>
void Prefetch(const std::vector<float>& v) {
  const char* p = reinterpret_cast<const char*>(v.data());
  for (std::size_t b = 0; b < v.size() * sizeof(float); b += 64) __builtin_prefetch(p + b, kWrite, 3);
}

}  // namespace

bool UniformGrid(std::span<const float> x, double& x0, double& dx) {
  const std::size_t n = x.size();
  if (n < 2) return false;
  x0 = x[0];
  dx = (static_cast<double>(x[n - 1]) - x0) / static_cast<double>(n - 1);
  if (!(dx > 0.0) || !std::isfinite(dx)) return false;
  // Each point's distance from its place, in floats (a hundredth of dx is
  // far above a float's rounding of x at a profiler's range); counted, not
  // branched on, so the loop runs eight points a register.
  const auto x0f = static_cast<float>(x0), dxf = static_cast<float>(dx), tolerance = 0.01f * dxf;
  int32_t off = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const float miss = x[k] - (x0f + static_cast<float>(static_cast<int32_t>(k)) * dxf);
    off += !(miss <= tolerance && miss >= -tolerance);  // (a NaN is off)
  }
  return off == 0;
}

void SensorRows::BeginLayer(int64_t layer) {
  if (layer == layer_) return;
  below_known_ = layer == layer_ + 1 && !current_.empty();
  for (Row& r : below_) spare_.push_back(std::move(r.z));
  below_.clear();
  std::swap(below_, current_);
  if (!below_known_) {
    for (Row& r : below_) spare_.push_back(std::move(r.z));
    below_.clear();
  }
  std::sort(below_.begin(), below_.end(), [](const Row& a, const Row& b) { return a.path_mm < b.path_mm; });
  layer_ = layer;
}

const float* SensorRows::Keep(double path_mm, double x0_bed_mm, double dx, std::span<const float> z, double frame_z) {
  dx_ = dx;
  Row row{path_mm, x0_bed_mm, {}};
  if (!spare_.empty()) row.z = std::move(spare_.back()), spare_.pop_back();
  row.z.resize(z.size());
  float* out = row.z.data();
  // In floats (the frame's offset rounded once more than bead measure's
  // doubles do: a float's step, 0.06 um at a metre).
  const auto f = static_cast<float>(frame_z);
  for (std::size_t k = 0; k < z.size(); ++k) out[k] = z[k] + f;
  current_.push_back(std::move(row));
  // The next profile's buffer, last written two layers ago, asked for now
  // (for writing), while this profile is measured.
  if (!spare_.empty()) Prefetch<1>(spare_.back());
  return out;
}

bool SensorRows::At(double path, Pair& out, std::string* why) const {
  if (!below_known_ || below_.empty()) {
    if (why) *why = "layer " + std::to_string(layer_ - 1) + " is not in the scan";
    return false;
  }
  std::size_t i = 0, j = 0;
  if (!PathNeighbours(
          below_, [](const Row& r) { return r.path_mm; }, path, options_.max_path_gap_mm, layer_ - 1, i, j, out.w, why))
    return false;
  // The row after these in the direction the head moves along the path,
  // which the profiles to come read next, asked of memory now (a row last
  // touched a layer ago; asked again while it is the next, a few
  // instructions where it is in the cache already).
  const std::size_t next = path >= last_path_ ? j + 1 : i - 1;  // (i = 0: past the end)
  if (next < below_.size()) Prefetch<0>(below_[next].z);
  last_path_ = path;
  out.count = i == j ? 1 : 2;
  const std::size_t rows[2] = {i, j};
  for (int r = 0; r < out.count; ++r) {
    const Row& row = below_[rows[r]];
    out.z[r] = row.z.data(), out.x0_mm[r] = row.x0_mm, out.size[r] = row.z.size();
  }
  return true;
}

}  // namespace bead::part
