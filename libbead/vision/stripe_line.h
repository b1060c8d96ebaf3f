// One image line across the stripe (stripe.h): its stripe-shaped peaks,
// and each estimator's sub-pixel centre of a peak. Internal to stripe.cc
// and the benchmark; instantiated for uint8_t, uint16_t and float.
#pragma once

#include <vector>

#include "libbead/vision/stripe.h"

namespace bead::vision::detail {

struct LinePeak {
  int first = 0, last = 0;         // the peak's run of equal samples (saturation: more than one)
  double value = 0.0;              // the peak sample
  double floor = 0.0;              // the higher of the darkest samples either side
  double left = 0.0, right = 0.0;  // where it crosses half height, px (linear between samples)
  double Height() const { return value - floor; }
  double Width() const { return right - left; }
};

enum class Verdict { kAccepted, kNoPeak, kTooWide, kTooNarrow, kFlatTop, kAtBorder };

struct LineScan {
  std::vector<LinePeak> peaks;          // stripe-shaped, in line order
  Verdict rejected = Verdict::kNoPeak;  // why the line has no stripe, when `peaks` is empty
  double rejected_rank = -1.0;
  double tallest = 0.0;  // the tallest candidate standing min_peak above both sides, whatever its shape
};

// saturated: the frame type's largest value (infinity for float frames).
template <typename T>
void ScanLine(const T* f, int n, const StripeOptions& options, double saturated, LineScan& out);

// cog, gaussian or parabolic (steger is 2-D: stripe_steger.h).
template <typename T>
double SubPixelCentre(const T* f, const LinePeak& peak, StripeMethod method, double threshold);

}  // namespace bead::vision::detail
