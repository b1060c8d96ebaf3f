// Occlusion: estimate what a profile's sensor could not see of its bead,
// and the bead's true area.
//
// The seen points (heights above the reference line, between the bead's
// edges and a little beyond) are fitted by each family of shape_models.h
// with Ceres under a Huber loss. Families are weighed by BIC
// (N ln(RSS/N) + k ln N, weights exp(-dBIC/2)). Each family's bias is its
// visible area (straight down, plus the fan's shadows when the rig gives
// the laser origin) minus its true area; its uncertainty comes from the
// fit's covariance (delta method). The estimate is the weighted mean; its
// uncertainty adds the spread across families. A family whose hidden part
// the data cannot fix (the rounded rectangle's bottom radius) contributes
// the middle of its possible range with the range's standard deviation,
// and the estimate is marked unconstrained when such families dominate.
//
// corrected area = measured area - bias; its uncertainty also holds the
// measured area's own (BeadGeometry::area_sigma_mm2).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "libbead/core/rig.h"
#include "libbead/profile/bead_geometry.h"
#include "libbead/core/profile_view.h"

namespace bead::occlusion {

struct FamilyFit {
  std::string family;
  bool ok = false;
  bool constrained = true;  // the data fixes its hidden part
  int points = 0, params = 0;
  double rss = 0, bic = 0, weight = 0;
  double true_area_mm2 = 0, visible_area_mm2 = 0;
  double bias_mm2 = 0, bias_sigma_mm2 = 0;
  double contact_width_mm = 0;  // where it meets the surface
  double max_width_mm = 0;
  double widest_height_mm = 0;  // height of the widest point (0: no undercut)
  std::vector<double> shape;    // fitted parameters, normalised by the height where it makes sense
};

struct OcclusionEstimate {
  bool ok = false;
  bool constrained = false;
  double bias_mm2 = 0, sigma_mm2 = 0;
  double corrected_area_mm2 = 0;
  std::string family;  // the heaviest
  std::vector<FamilyFit> families;
  std::string note;
};

struct OcclusionOptions {
  std::optional<LaserOrigin> laser_origin;  // the fan; none: rays straight down
  double huber_mm = 0.03;                   // robust loss scale on heights
  double margin_mm = 0.5;                   // surface points kept beyond each edge
};

// Fits the bead of one measured profile (geometry must be valid).
// Defined in bead::occlusion, which links Ceres; the types above and the
// pooling (occlusion_pool.h) are in bead::occlusion_pool, which does not.
OcclusionEstimate EstimateOcclusion(const ProfileView& view, const BeadGeometry& geometry,
                                    const OcclusionOptions& options);

// What a stage that estimates occlusion is handed: EstimateOcclusion, or a
// function that loads it when first called (the bead tool's programs load
// Ceres only when a fit runs).
using Estimator = OcclusionEstimate (*)(const ProfileView&, const BeadGeometry&, const OcclusionOptions&);

}  // namespace bead::occlusion
