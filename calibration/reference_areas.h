// Reference areas from a run: where the bare surface lies either side of
// the bead over the whole run, for a rig file whose areas are new or
// doubtful (bead calibrate reference).
//
// Each profile gets a line fitted robustly to all its points (the line
// through two of its tenths' medians that most others lie on, then least
// squares near it: a bead, a rim or a clamp is a minority); points standing above it by more than the detection
// threshold (max(threshold_mm, threshold_sigmas x the fit's RMS), as
// bead measure uses), with the median of five about them, stand up (a
// reflection's spike of one or two points does not). The bead of a profile is its connected
// raised run with the largest integral. Over the run, on bins across the
// field: how often each holds data and how often it is raised. Each area
// starts a margin beyond the bead's outermost edge over the run and grows
// outward over bins that hold data in most profiles and are seldom raised,
// up to the first that is not (the field's end, a rim, a clamp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "libbead/core/profile_view.h"
#include "libbead/core/rig.h"
#include "libbead/io/profile_stream.h"

namespace bead::calibration {

struct ReferenceSurveyOptions {
  double threshold_mm = 0.05;          // detection threshold, as bead measure's default
  double threshold_sigmas = 6.0;       // ... or this many line RMS, when larger
  double max_gap_mm = 1.0;             // a bead's run bridges dropouts this long
  double margin_mm = 1.0;              // from the bead's outermost edge to an area
  double edge_quantile = 0.001;        // the bead's outermost edges: this quantile of each side
  double min_data_fraction = 0.9;      // a bin belongs to an area when it holds data this often ...
  double max_raised_fraction = 0.005;  // ... and is raised at most this often
  double min_area_mm = 2.0;            // an area narrower is an error
};

struct ProposedArea {
  ReferenceArea area;
  double points_per_profile = 0;  // valid points in it, on average
  double clear_fraction = 0;      // of the profiles with a bead: none of its points raised
};

struct ReferenceSurvey {
  std::size_t profiles = 0, with_line = 0, with_bead = 0;
  double field_min_mm = 0, field_max_mm = 0, spacing_mm = 0;
  double bead_left_mm[2] = {0, 0};   // the bead's left edge over the run: outermost, median
  double bead_right_mm[2] = {0, 0};  // its right edge: outermost, median
  ProposedArea left, right;
};

// Accumulates profiles, then proposes the areas.
class ReferenceSurveyor {
 public:
  explicit ReferenceSurveyor(ReferenceSurveyOptions options = {}) : options_(options) {}
  void Add(const ProfileView& profile);
  // Throws bead::Error saying what is missing (no bead, no room either side).
  ReferenceSurvey Propose() const;
  // How often `area` stays clear of raised points over the profiles with a
  // bead (a rig file's own areas, for comparison); NaN before any profile.
  double ClearFraction(const ReferenceArea& area) const;

 private:
  struct Raised {
    std::vector<uint16_t> bins;  // the bins raised in one profile
  };
  std::size_t Bin(double x) const;
  ReferenceSurveyOptions options_;
  std::vector<double> seg_x_, seg_z_;            // scratch of the surface line
  std::vector<std::pair<float, float>> points_;  // x, height of one profile
  std::vector<uint8_t> up_;                      // ... standing up
  bool grid_ = false;
  double x0_ = 0, bin_mm_ = 0;
  std::size_t bins_ = 0;
  std::vector<uint32_t> data_count_, raised_count_, point_count_;
  std::vector<Raised> raised_;  // profiles with a bead
  std::vector<double> left_edges_, right_edges_;
  std::vector<double> spacings_;
  std::size_t profiles_ = 0, with_line_ = 0;
  double field_min_ = 1e300, field_max_ = -1e300;
};

// The profiles of `stream`, at most `max_profiles` spread evenly over it,
// added to `surveyor` window by window; returns the stride taken.
std::size_t SurveyStream(ProfileStream& stream, std::size_t max_profiles, ReferenceSurveyor& surveyor);

}  // namespace bead::calibration
