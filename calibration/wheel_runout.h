// The wheel's runout from a run: the reference line's height at the laser
// against the wheel's angle (`bead calibrate wheel`).
//
// The wheel point under the laser at encoder angle theta is the point that
// lay under the nozzle `offset` counts earlier; its distance from the axle,
// R + h(theta), sets both the surface's height at the laser (h) and the
// surface speed it had under the nozzle, omega (R + h). So the height
// measured at the laser is the radius error of the very material's
// footing, and an eccentric wheel (centre e off the axle) shows as
// h = e cos(theta - phase) to first order in e / R.
//
// Model, by least squares over the profiles with a reference line:
//   h_k = drift(t_k) + a1 cos theta_k + b1 sin theta_k + a2 cos 2 theta_k + b2 sin 2 theta_k
// with drift a cubic in time (the wheel warming, the sensor settling).
// theta is the encoder's angle, 2 pi counts / counts_per_rev, counts
// anchored to the raw counter (so the phase holds between runs while the
// counter keeps its zero; an encoder reset needs a new calibration).
// Standard errors from the residual, inflated by (1 + rho) / (1 - rho) for
// the residual's lag-one correlation rho; intervals 95 % (1.96 se).
#pragma once

#include <vector>

#include "libbead/core/rig.h"

namespace bead::calibration {

struct WheelRunout {
  int profiles_used = 0;
  double turns = 0.0;            // revolutions the run covers
  double eccentricity_mm = 0.0;  // once-per-revolution amplitude, e
  double eccentricity_ci95_mm = 0.0;
  double phase_deg = 0.0;  // encoder angle at which h is highest, [0, 360)
  double phase_ci95_deg = 0.0;
  double twice_mm = 0.0;  // twice-per-revolution amplitude (an oval wheel)
  double twice_ci95_mm = 0.0;
  double twice_phase_deg = 0.0;  // the first of its two highs
  double runout_mm = 0.0;        // peak to peak of the fitted once + twice curve (a dial's reading)
  double drift_mm = 0.0;         // range of the fitted drift over the run
  double residual_rms_mm = 0.0;
  double inflation = 1.0;  // the variance inflation for correlated residuals
};

// counts: each profile's unwrapped wheel position (encoder counts,
// anchored to the raw counter); height_mm: the reference line's height at
// the laser (NaN where the profile has none). Throws bead::Error when the
// run covers less than one turn or too few profiles have a height.
WheelRunout FitWheelRunout(const Rig& rig, const std::vector<double>& t_s, const std::vector<double>& counts,
                           const std::vector<double>& height_mm);

}  // namespace bead::calibration
