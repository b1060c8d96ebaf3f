#include "libbead/vision/stripe_line.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace bead::vision::detail {
namespace {

// The offset of a peak from its middle sample, from the samples before
// (a), at (c) and after (d) it, above the floor: the three-point Gaussian
// when all three are positive (Fisher and Naidu 1996), else the parabola.
double GaussianOffset(double a, double c, double d) {
  if (a > 0.0 && c > 0.0 && d > 0.0) {
    const double la = std::log(a), lc = std::log(c), ld = std::log(d);
    const double curvature = la - 2.0 * lc + ld;
    if (curvature < 0.0) return 0.5 * (la - ld) / curvature;
  }
  const double curvature = a - 2.0 * c + d;
  return curvature < 0.0 ? 0.5 * (a - d) / curvature : 0.0;
}

double ParabolaOffset(double a, double c, double d) {
  const double curvature = a - 2.0 * c + d;
  return curvature < 0.0 ? 0.5 * (a - d) / curvature : 0.0;
}

// Classifies the candidate whose equal-valued run is [first, last].
template <typename T>
Verdict Examine(const T* f, int n, int first, int last, const StripeOptions& o, double saturated, LinePeak& p) {
  const int reach = static_cast<int>(std::ceil(o.max_width_px));
  p.first = first, p.last = last, p.value = static_cast<double>(f[first]);
  // The darkest sample each side within reach; a side cut off by the
  // frame's edge takes the other side's.
  double left_floor = p.value, right_floor = p.value;
  for (int i = std::max(0, first - reach); i < first; ++i) left_floor = std::min(left_floor, static_cast<double>(f[i]));
  for (int i = last + 1; i <= std::min(n - 1, last + reach); ++i)
    right_floor = std::min(right_floor, static_cast<double>(f[i]));
  if (first == 0) left_floor = right_floor;
  if (last == n - 1) right_floor = left_floor;
  p.floor = std::max(left_floor, right_floor);
  if (p.Height() < o.min_peak) return Verdict::kNoPeak;
  if (first == 0 || last == n - 1) return Verdict::kAtBorder;
  const double half = p.floor + 0.5 * p.Height();
  int i = first;
  while (i > 0 && f[i - 1] > half) --i;  // ends within reach: the left floor is below half
  if (i == 0) return Verdict::kAtBorder;
  p.left = (i - 1) + (half - f[i - 1]) / (static_cast<double>(f[i]) - f[i - 1]);
  int j = last;
  while (j < n - 1 && f[j + 1] > half) ++j;
  if (j == n - 1) return Verdict::kAtBorder;
  p.right = j + (static_cast<double>(f[j]) - half) / (static_cast<double>(f[j]) - f[j + 1]);
  if (p.Width() > o.max_width_px) return Verdict::kTooWide;
  if (p.Width() < o.min_width_px) return Verdict::kTooNarrow;
  // A lit region's profile is a box: as wide at 3/4 of its height as at
  // half, noise or not. A Gaussian stripe is 0.64 times as wide there
  // (2 sigma sqrt(2 ln(4 / 3)) against 2 sigma sqrt(2 ln 2)); a blurred
  // or speckled one a little more. Above 0.85 the peak is flat-topped,
  // which only saturation excuses. Widths between samples as for the half
  // height; not tested under 6 px at half height, where a speckled
  // stripe's few samples cannot tell a flat top from a round one.
  if (p.value < saturated && p.Width() >= 6.0) {
    const double top = p.floor + 0.75 * p.Height();
    int a = first, b = last;
    while (a > 0 && f[a - 1] > top) --a;
    while (b < n - 1 && f[b + 1] > top) ++b;
    const double left = a > 0 ? (a - 1) + (top - f[a - 1]) / (static_cast<double>(f[a]) - f[a - 1]) : a;
    const double right = b < n - 1 ? b + (static_cast<double>(f[b]) - top) / (static_cast<double>(f[b]) - f[b + 1]) : b;
    if (right - left > 0.85 * p.Width()) return Verdict::kFlatTop;
  }
  return Verdict::kAccepted;
}

}  // namespace

template <typename T>
void ScanLine(const T* f, int n, const StripeOptions& o, double saturated, LineScan& out) {
  out.peaks.clear();
  out.rejected = Verdict::kNoPeak;
  out.rejected_rank = -1.0;
  out.tallest = 0.0;
  if (n < 3) return;
  T lo = f[0];
  for (int i = 1; i < n; ++i) lo = std::min(lo, f[i]);
  const double level = std::max(static_cast<double>(lo) + o.min_peak, o.threshold);
  const int reach = static_cast<int>(std::ceil(o.max_width_px));
  // Local maxima at or above the level (a run of equal samples counts
  // once, at its end); of those closer than `reach`, the higher.
  int kept_first = -1, kept_last = -1;
  auto examine_kept = [&]() {
    if (kept_first < 0) return;
    LinePeak p;
    const Verdict v = Examine(f, n, kept_first, kept_last, o, saturated, p);
    if (v != Verdict::kNoPeak) out.tallest = std::max(out.tallest, p.Height());
    if (v == Verdict::kAccepted) {
      out.peaks.push_back(p);
      return;
    }
    // The line's reason: the tallest stripe-high candidate's that was too
    // wide or narrow, else a peak running off the frame, else no peak.
    const double rank = v == Verdict::kNoPeak ? 0.0 : v == Verdict::kAtBorder ? 1.0 : 2.0 + p.Height();
    if (rank > out.rejected_rank) out.rejected = v, out.rejected_rank = rank;
  };
  for (int i = 0; i < n; ++i) {
    if (static_cast<double>(f[i]) < level) continue;
    if (i + 1 < n && !(f[i] > f[i + 1])) continue;  // still rising or level
    int first = i;
    while (first > 0 && f[first - 1] == f[i]) --first;
    if (first > 0 && f[first - 1] > f[i]) continue;  // a shoulder on the way down
    if (kept_first >= 0 && first - kept_last <= reach) {
      if (f[i] > f[kept_last]) kept_first = first, kept_last = i;
      continue;
    }
    examine_kept();
    kept_first = first, kept_last = i;
  }
  examine_kept();
}

template <typename T>
double SubPixelCentre(const T* f, const LinePeak& p, StripeMethod method, double threshold) {
  const int a = p.first, b = p.last;
  switch (method) {
    case StripeMethod::kCentreOfGravity: {
      const double cut = threshold > 0.0 ? std::max(threshold, p.floor) : p.floor + 0.5 * p.Height();
      double sum = 0.0, moment = 0.0;
      for (int i = a; static_cast<double>(f[i]) > cut; --i) sum += f[i] - cut, moment += (f[i] - cut) * i;
      for (int i = a + 1; static_cast<double>(f[i]) > cut; ++i) sum += f[i] - cut, moment += (f[i] - cut) * i;
      return sum > 0.0 ? moment / sum : 0.5 * (a + b);
    }
    case StripeMethod::kGaussian:
    case StripeMethod::kParabolic: {
      if (b > a) return 0.5 * (a + b);  // a flat (saturated) top: its middle
      const double fl = method == StripeMethod::kGaussian ? p.floor : 0.0;
      const double l = f[a - 1] - fl, c = f[a] - fl, r = f[a + 1] - fl;
      return a + (method == StripeMethod::kGaussian ? GaussianOffset(l, c, r) : ParabolaOffset(l, c, r));
    }
    case StripeMethod::kSteger:
      break;
  }
  return 0.5 * (a + b);
}

template void ScanLine<std::uint8_t>(const std::uint8_t*, int, const StripeOptions&, double, LineScan&);
template void ScanLine<std::uint16_t>(const std::uint16_t*, int, const StripeOptions&, double, LineScan&);
template void ScanLine<float>(const float*, int, const StripeOptions&, double, LineScan&);
template double SubPixelCentre<std::uint8_t>(const std::uint8_t*, const LinePeak&, StripeMethod, double);
template double SubPixelCentre<std::uint16_t>(const std::uint16_t*, const LinePeak&, StripeMethod, double);
template double SubPixelCentre<float>(const float*, const LinePeak&, StripeMethod, double);

}  // namespace bead::vision::detail
