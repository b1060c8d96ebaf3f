// The laser stripe in a camera frame: for each image column u, the row v
// of the stripe's centre, to a fraction of a pixel.
//
// Per column: the brightest row; its two neighbours above the column's
// darkest value (the background) give the centre by the three-point
// Gaussian estimator (Fisher and Naidu 1996, "A comparison of algorithms
// for subpixel peak detection": the parabola through the logarithms of
// three samples of a Gaussian peaks exactly at the Gaussian's centre);
// the parabola through the samples themselves where a neighbour is at the
// background. A saturated peak (the frame type's largest value) is flat:
// its centre is the middle of the saturated run. A column whose peak does
// not stand min_peak above its background, or peaks on the frame's first
// or last row, has no stripe (NaN).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace bead::vision {

struct StripeOptions {
  // Least height of the peak above the column's background, grey levels.
  double min_peak = 20.0;
};

// rows_px gets frame.cols values. The frame: one channel, 8- or 16-bit
// unsigned or 32-bit float; anything else throws bead::Error.
void StripeCentres(const cv::Mat& frame, const StripeOptions& options, std::vector<float>& rows_px);

}  // namespace bead::vision
