// The laser stripe in a camera frame: along each image line that crosses
// it, the stripe's centre to a fraction of a pixel.
//
// The stripe runs along the image's rows (across the frame: one centre per
// column, a row number) or along its columns (down the frame, as a camera
// mounted the other way sees it: one centre per row, a column number).
// `axis` says which; `auto` tries both on the frame and keeps the one that
// finds the stripe on more lines.
//
// A peak counts as the stripe only when it is shaped like one:
// - it stands min_peak grey levels above the darkest sample on EACH side
//   within max_width_px (so a step between a dark and a light chessboard
//   square, or a bright region's edge, is no peak), and reaches
//   `threshold` when one is set;
// - its full width at half height (above the higher of those two floors)
//   lies within [min_width_px, max_width_px] (a lit square or the
//   background is too wide, a hot pixel too narrow);
// - unless saturated, it is not flat-topped: at 3/4 of its height it is
//   at most 0.85 times as wide as at half (a Gaussian: 0.64; a lit
//   chessboard square narrower than max_width_px: about 1);
// - its half-height extent stays inside the frame.
// - it is not faint against the frame's stripe: at least min_relative
//   times the 95th percentile over the lines of their tallest peak of any
//   width (a laser stripe is about as bright along its length; a frame's
//   squares, edges and glare stand far lower, and where the stripe
//   crosses few lines they would otherwise be most of what is found).
// Several stripe-shaped peaks on one line (a reflection, a second surface)
// are resolved by `rule`; the count of such lines is reported.
//
// Centre estimators (`method`), each on the chosen peak:
// - cog: centre of gravity of the samples above the cut, weights the
//   excess over it; the cut is `threshold` when set, else half height.
//   What line profilers do by default.
// - gaussian: three-point Gaussian (Fisher and Naidu 1996, "A comparison
//   of algorithms for subpixel peak detection": the parabola through the
//   logarithms of three samples above the floor peaks at a sampled
//   Gaussian's exact centre).
// - parabolic: the parabola through the three samples themselves.
// - steger: Steger's curvilinear-structure detector (C. Steger, "An
//   unbiased detector of curvilinear structures", IEEE PAMI 20(2), 1998):
//   the image's Hessian from Gaussian derivatives at scale sigma confirms
//   a bright line (its most negative eigenvalue dominates) not running
//   along the searched line; the centre is where the first derivative of
//   the line's smoothed profile vanishes (sec. 2 and 3, in 1-D along the
//   searched line: 2-D smoothing would pull a curved stripe's ridge
//   toward its centre of curvature by sigma^2 k / 2). sigma >= w / sqrt(3)
//   for a bar of half-width w (Steger's condition for a single maximum),
//   taken as the peak's measured full width / 3 unless steger_sigma_px is
//   set: so the method suits wide, flat-topped (saturated) stripes.
// A saturated peak (the frame type's largest value) is flat: gaussian and
// parabolic take the middle of its saturated run; cog and steger see it
// whole. Saturated lines are counted.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace bead::vision {

enum class StripeAxis { kAuto, kRows, kColumns };  // the direction the stripe runs in the image
enum class StripeMethod { kCentreOfGravity, kGaussian, kParabolic, kSteger };
enum class PeakRule { kStrongest, kWidest, kFirst, kLast, kNearest };

struct StripeOptions {
  StripeAxis axis = StripeAxis::kAuto;
  StripeMethod method = StripeMethod::kGaussian;
  PeakRule rule = PeakRule::kStrongest;
  double min_peak = 20.0;        // least height above the floor on each side, grey levels
  double threshold = 0.0;        // least peak value, grey levels (0: none); cog's cut when set
  double min_width_px = 1.5;     // full width at half height, px (a lone hot pixel is 1)
  double max_width_px = 40.0;    // also the reach of the floor search on each side
  double steger_sigma_px = 0.0;  // 0: from each peak's width
  double min_relative = 0.25;    // of the frame's stripe height (0: no test)
};

// What became of the lines searched: every line is in exactly one of
// found, no_peak, too_wide, too_narrow, flat_top, at_border, unresolved, faint.
struct StripeStats {
  int lines = 0;
  int found = 0;
  int no_peak = 0;     // nothing stood min_peak above both sides (and reached threshold)
  int too_wide = 0;    // the best candidate was wider than max_width_px
  int too_narrow = 0;  // ... narrower than min_width_px
  int flat_top = 0;    // ... flat-topped below saturation
  int at_border = 0;   // ... ran off the frame
  int unresolved = 0;  // steger: no stripe-like curvature there, or the stripe runs along the line
  int faint = 0;       // the chosen peak was under min_relative of the frame's stripe
  int several = 0;     // of the found: lines with more than one stripe-shaped peak
  int saturated = 0;   // of the found: lines whose chosen peak was saturated
  StripeStats& operator+=(const StripeStats& o);
};

struct StripeCentres {
  StripeAxis axis = StripeAxis::kRows;  // the axis used (never kAuto)
  // One value a line: for kRows, centres[u] is the row of the stripe in
  // column u; for kColumns, centres[v] is its column in row v. NaN: none.
  std::vector<float> centres;
  StripeStats stats;
  // The image point (column, row) of line k's centre.
  cv::Point2d Pixel(std::size_t k) const {
    return axis == StripeAxis::kRows ? cv::Point2d(static_cast<double>(k), centres[k])
                                     : cv::Point2d(centres[k], static_cast<double>(k));
  }
};

// The frame: one channel, 8- or 16-bit unsigned or 32-bit float; anything
// else, or options out of range, throws bead::Error. `out` is reused.
void FindStripe(const cv::Mat& frame, const StripeOptions& options, StripeCentres& out);

// Names as the command line and sensor.yaml spell them (axis: auto, rows,
// columns; method: cog, gaussian, parabolic, steger; rule: strongest,
// widest, first, last, nearest); Parse* throw bead::Error listing the
// accepted names.
std::string Name(StripeAxis axis);
std::string Name(StripeMethod method);
std::string Name(PeakRule rule);
StripeAxis ParseStripeAxis(const std::string& name);
StripeMethod ParseStripeMethod(const std::string& name);
PeakRule ParsePeakRule(const std::string& name);

// One line per non-zero count, e.g. "1024 lines: 988 found (412 saturated,
// 3 with several peaks), 30 no peak, 6 too wide".
std::string Describe(const StripeStats& stats);

}  // namespace bead::vision
