// GatherPoints: one pass over a profile that every later stage shares:
// the valid points (finite x and z) in increasing x (w.order), and the
// valid points inside each reference area (w.left_*, w.right_*).
#pragma once

#include "libbead/core/rig.h"
#include "libbead/profile/profile.h"
#include "libbead/profile/workspace.h"

namespace bead {

void GatherPoints(const ProfileView& view, const ReferenceArea& left, const ReferenceArea& right,
                  ProfileWorkspace& workspace);

}  // namespace bead
