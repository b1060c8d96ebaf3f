// Reference line: the bare wheel surface either side of the bead, fitted as
// z = intercept + slope * x over the rig's two reference areas. Robust to
// NaN dropouts, reflection spikes (well beyond 20 % of the reference
// points), sensor roll (slope) and wheel runout (intercept moves).
//
// Method: a start through the centre of each area's 48 samples (six spots
// of eight adjacent points spread over the area; every stride-th valid
// point where an area is small or riddled with dropouts): the median of
// their medians of three, which survives any arrangement of up to a third
// of them being spikes (reference_line.cc says more); then a least-squares
// refit on the points within `inlier_sigmas` robust standard deviations
// (1.4826 * MAD of the start's residuals) of the start. More refits, each
// within the previous fit's RMS, are an option; over 20000 profiles with
// 20 % spikes and 5 % dropouts a second one changed neither the slope's nor
// the intercept's error (3.6e-5, 0.65 um). The last refit's inliers and
// their RMS are reported.
#pragma once

#include <limits>

#include "libbead/core/rig.h"
#include "libbead/profile/point_set.h"
#include "libbead/core/profile_view.h"
#include "libbead/profile/workspace.h"

namespace bead {

struct ReferenceLineOptions {
  // Inlier band around the line, in robust standard deviations.
  double inlier_sigmas = 3.5;
  // Floor on the robust standard deviation, mm. A noiseless or coarsely
  // quantised profile would otherwise reject points that sit a rounding
  // step off the line.
  double min_sigma_mm = 0.002;
  // Fewest valid points each area must hold for a fit.
  int min_points_per_area = 5;
  // Least-squares refits after the median start (at least one).
  int iterations = 1;
  // At most this many points per area enter each median (evenly strided);
  // keeps the robust start cheap on long profiles.
  int max_median_samples = 48;
};

struct ReferenceLine {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  bool ok = false;
  double intercept_mm = kNaN;     // z of the line at x = 0
  double slope = kNaN;            // dz/dx (tan of the sensor roll)
  double residual_rms_mm = kNaN;  // RMS perpendicular distance of the inliers
  int points_used = 0;            // inliers of the final fit
  int points_available = 0;       // valid points in both areas

  // Perpendicular height of (x, z) above the line, mm.
  double HeightAt(double x_mm, double z_mm) const;
};

// Fits the line to a prepared point set (point_set.h), with the
// workspace's scratch buffers. On failure (an area with too few valid
// points) returns ok = false.
ReferenceLine FitReferenceLine(const PointSet& points, const ReferenceArea& left, const ReferenceArea& right,
                               const ReferenceLineOptions& options, ProfileWorkspace& workspace);

// The same from a view (prepares its points in the workspace).
ReferenceLine FitReferenceLine(const ProfileView& view, const ReferenceArea& left, const ReferenceArea& right,
                               const ReferenceLineOptions& options, ProfileWorkspace& workspace);

}  // namespace bead
