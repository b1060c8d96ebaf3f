#include "libbead/profile/profile_processor.h"

#include "libbead/profile/kernel.h"

namespace bead {

ProfileProcessor::ProfileProcessor(const ReferenceArea& left, const ReferenceArea& right, const ProfileOptions& options,
                                   std::size_t max_points)
    : left_(left), right_(right), options_(options), workspace_(max_points), kernel_(&ActiveKernel()) {}

const BeadGeometry& ProfileProcessor::Process(const ProfileView& view) {
  result_ = kernel_->process(view, left_, right_, options_, workspace_);
  return result_;
}

BeadGeometry MeasureProfile(const ProfileView& view, const ReferenceArea& left, const ReferenceArea& right,
                            const ProfileOptions& options) {
  ProfileProcessor processor(left, right, options, view.x_mm.size());
  return processor.Process(view);
}

}  // namespace bead
