// The kernel's table of entry points (built once per instruction set, as
// kernel.h says).
#include "libbead/profile/kernel.h"

namespace bead::BEAD_KERNEL {
namespace {

BeadGeometry Process(const ProfileView& view, const ReferenceArea& left, const ReferenceArea& right,
                     const ProfileOptions& options, ProfileWorkspace& workspace) {
  // Qualified: the public functions of the same names are found too.
  const PointSet points = BEAD_KERNEL::PreparePoints(view, workspace);
  const ReferenceLine line = BEAD_KERNEL::FitReferenceLine(points, left, right, options.reference, workspace);
  return BEAD_KERNEL::MeasureBead(points, line, left, right, options.bead, workspace);
}

#define BEAD_STRINGIFY_(x) #x
#define BEAD_STRINGIFY(x) BEAD_STRINGIFY_(x)
constexpr ProfileKernel kKernel{BEAD_STRINGIFY(BEAD_KERNEL),   BEAD_KERNEL::PreparePoints, BEAD_KERNEL::CountFiniteZ,
                                BEAD_KERNEL::FitReferenceLine, BEAD_KERNEL::MeasureBead,   Process};

}  // namespace

const ProfileKernel& Kernel() { return kKernel; }

}  // namespace bead::BEAD_KERNEL
