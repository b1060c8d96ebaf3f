#include "libbead/profile/profile_processor.h"

#include "libbead/profile/point_set.h"

namespace bead {

ProfileProcessor::ProfileProcessor(const ReferenceArea& left, const ReferenceArea& right,
                                   const ProfileOptions& options, std::size_t max_points)
    : left_(left), right_(right), options_(options), workspace_(max_points) {}

const BeadGeometry& ProfileProcessor::Process(const ProfileView& view) {
  const PointSet points = PreparePoints(view, workspace_);
  const ReferenceLine line = FitReferenceLine(points, left_, right_, options_.reference, workspace_);
  result_ = MeasureBead(points, line, left_, right_, options_.bead, workspace_);
  return result_;
}

BeadGeometry MeasureProfile(const ProfileView& view, const ReferenceArea& left, const ReferenceArea& right,
                            const ProfileOptions& options) {
  ProfileProcessor processor(left, right, options, view.x_mm.size());
  return processor.Process(view);
}

}  // namespace bead
