// Steger's sub-pixel line centre (stripe.h) at one image line's peak.
// Internal to stripe.cc.
#pragma once

#include <opencv2/core.hpp>

namespace bead::vision::detail {

// lines: the frame with the searched lines as its rows (one channel, 8U,
// 16U or 32F). Starting at pixel (x, y) of line y, the position along
// line y of the stripe's centre, px: where the derivative of the line's
// profile, smoothed with a Gaussian of sigma_px, vanishes. False when the
// image's Hessian there (2-D Gaussian derivatives) shows no bright line
// (its most negative eigenvalue does not dominate) or a line running
// within about 11 degrees of the searched line, or the zero is not found
// within 4 px. Lines within 3 sigma of the frame's first or last are
// not checked in 2-D.
bool StegerCentre(const cv::Mat& lines, int x, int y, double sigma_px, double& centre);

}  // namespace bead::vision::detail
