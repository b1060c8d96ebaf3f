// Nozzle-to-laser encoder offset from pin scans (thesis 3.1.1 and eq. 19:
// offset = p_max - p_start), done better than the argmax of one scan:
//
// Per scan: each profile's chord width of the pin (the bead width of the
// profile geometry) against the counts travelled since the pin stood under
// the nozzle. A cylinder of radius R crossing the laser plane shows the
// chord w(c) = 2 sqrt(R^2 - ((c - c0) mm_per_count)^2) + b (b: what the
// sensor adds at the base, such as the fan's shadow). c0 is fitted with
// Ceres (Cauchy loss at the width resolution) from a closed-form start (w^2
// is exactly quadratic in c), with its standard error and the fit RMS.
//
// Pooling: a scan is an outlier when its c0 lies more than 3.5 robust
// standard deviations (1.4826 MAD, floored at three times the scans' median
// fit standard error) from the median of all scans. The offset is the mean
// of the others, with the 95 % interval t_{0.975, n-1} s / sqrt(n), where
// s is never below the scans' median fit standard error: a scan's centre is
// not known better than its own fit says, so scans that agree more closely
// than that (identical scans, one scan copied) do not shrink the interval
// to nothing; the calibration says so in `note`.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "libbead/core/rig.h"
#include "libbead/io/run_archive.h"
#include "libbead/profile/profile_processor.h"

namespace bead::calibration {

struct PinScanFit {
  int64_t start_encoder = 0;
  int profiles = 0;          // profiles in the scan
  int profiles_on_pin = 0;   // profiles that saw the pin
  double center_counts = 0;  // c0: counts from the start to the pin centre
  double center_se_counts = 0;
  double radius_mm = 0;
  double rms_mm = 0;         // RMS chord-width residual of the fit
  double argmax_counts = 0;  // the thesis' estimate, for comparison
  bool ok = false;
  bool outlier = false;
  std::string reason;  // why not ok
};

struct OffsetOptions {
  ProfileOptions profile;
  double outlier_sigmas = 3.5;
  int min_profiles_on_pin = 5;
};

struct OffsetCalibration {
  std::vector<PinScanFit> scans;
  double offset_counts = 0;
  double offset_mm = 0;
  double ci95_counts = 0;  // half width
  double ci95_mm = 0;
  double sd_counts = 0;  // scan-to-scan standard deviation
  int used = 0;
  int total = 0;
  bool ok = false;
  std::string reason;
  std::string note;  // what is odd but not fatal (scans closer than their fit errors)
};

PinScanFit FitPinScan(const Rig& rig, const PinScan& scan, const OffsetOptions& options = {});
OffsetCalibration CalibrateOffset(const Rig& rig, const PinScanArchive& pins, const OffsetOptions& options = {});

}  // namespace bead::calibration
