// ProfileProcessor: the per-profile geometry for acquisition software. It
// owns its buffers, sized for `max_points` at construction, and allocates
// nothing per profile unless a profile is longer than any before it.
// The batch tools use the same class, so on-line and off-line agree.
//
//   bead::ProfileProcessor processor(rig.reference_left, rig.reference_right, {}, 640);
//   for (...) { const bead::BeadGeometry& g = processor.Process(view); ... }
#pragma once

#include <cstddef>

#include "libbead/core/rig.h"
#include "libbead/profile/bead_geometry.h"
#include "libbead/profile/reference_line.h"
#include "libbead/profile/workspace.h"

namespace bead {

struct ProfileKernel;

struct ProfileOptions {
  ReferenceLineOptions reference;
  BeadOptions bead;
};

class ProfileProcessor {
 public:
  ProfileProcessor(const ReferenceArea& left, const ReferenceArea& right, const ProfileOptions& options = {},
                   std::size_t max_points = 2048);

  // Geometry of one profile; the reference stays valid until the next call.
  const BeadGeometry& Process(const ProfileView& view);

  const ProfileOptions& options() const { return options_; }

 private:
  ReferenceArea left_, right_;
  ProfileOptions options_;
  ProfileWorkspace workspace_;
  const ProfileKernel* kernel_;  // kernel.h: the build this processor runs
  BeadGeometry result_;
};

// One-off convenience (allocates its own buffers).
BeadGeometry MeasureProfile(const ProfileView& view, const ReferenceArea& left, const ReferenceArea& right,
                            const ProfileOptions& options = {});

}  // namespace bead
